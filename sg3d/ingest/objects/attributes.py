"""Per-object 3-D attributes from a 2-D box in one frame (paper Sec. V-B, Eq. 8-9).

Boxes are (x1, y1, x2, y2) in colour pixels, x2/y2 exclusive, clipped to the image.

- Position (Eq. 8): the box is split 5x5 and the centre cell's pixels with depth are lifted to
  world coordinates; their per-axis mean and variance form the position Gaussian. When the
  centre cell has fewer than `MIN_CENTRE_POINTS` depths (thin objects, holes, black surfaces)
  the centre 3x3 cells are used instead. Depths far from the region's median (more than
  max(10 cm, 3 robust sigmas)) are dropped first: a centre cell that looks through a handle or
  past a chair's slats should not drag the object onto the wall behind it. None without depth.
- Size: the object's points are the box pixels connected (no depth jump) to the centre
  region, which separates the object from background seen around it (the floor's pixels, within
  FLOOR_BAND_M of the build's floor height, left out first: `floor_pixels`); their extent between the
  5th and 95th percentile along (e1, e2, up) of `sg3d.core.geometry.horizontal_basis(up)` gives
  (width, depth, height), the frame relations reason in.
- Colour histogram (Eq. 9): HSV, HIST_BINS per axis (OpenCV ranges H 0-180, S and V 0-256),
  counts (sums to the number of box pixels).
- Colour (`object_colour`): the object's own pixels (the box's inner region on the depth surface
  connected to the centre, as for the size, and at the object's own depth; the whole inner
  region when depth covers too little of it; a screen's whole box), the cast of the light on it
  (estimated on its surround, the frame's screens left out) divided out, named by `sg3d.ingest.objects.colour.read_colour`; the view's weight for
  the vote across views (`sg3d.ingest.objects.colour.view_weight`) from its size, sharpness and whether the
  image border cuts the box.
- Thumbnail: JPEG bytes of the box, longest side at most 128 px.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import cv2
import numpy as np
from numpy.typing import ArrayLike

from sg3d.core.geometry import Ground, horizontal_frame
from sg3d.core.model import HIST_BINS, vec3
from sg3d.ingest.objects import colour as colour_model
from sg3d.ingest.readers.frames import Frame

Box = Sequence[float]

MIN_CENTRE_POINTS = 10
THUMBNAIL_SIDE = 128
# A neighbouring pixel belongs to the same surface unless depth jumps by more than this
# (absolute metres, or relative to the depth: Kinect noise grows with range).
DEPTH_JUMP_M = 0.04
DEPTH_JUMP_REL = 0.03
# A box's 3-D extent is measured on a pixel grid of about this many samples: percentiles of a
# 6,400-point sample are as good as of a 120,000-pixel table box, at a twentieth of the cost.
MAX_BOX_SAMPLES = 6400
# A box's extent is measured between these percentiles of the object's points.
BOX_LOW_PERCENTILE, BOX_HIGH_PERCENTILE = 5.0, 95.0
# A box's points within this height of the floor are the floor (Kinect-class depth noise of 1-2 cm
# at 2-3 m plus a 2-3 degree tilt of the floor estimate across a room), left out of its extent...
FLOOR_BAND_M = 0.05
# ... unless that leaves under this share of the box's depth: a thing lying flat on the floor.
MIN_OFF_FLOOR_SHARE = 0.2


def clip_box(box: Box, width: int, height: int) -> tuple[int, int, int, int]:
    """Integer pixel bounds [x1, x2) x [y1, y2) inside the image; ValueError when empty."""
    x1, y1, x2, y2 = (float(v) for v in box)
    ix1, iy1 = max(0, int(np.floor(x1))), max(0, int(np.floor(y1)))
    ix2, iy2 = min(width, int(np.ceil(x2))), min(height, int(np.ceil(y2)))
    if ix2 <= ix1 or iy2 <= iy1:
        raise ValueError(f"box {tuple(box)} is empty inside a {width}x{height} image")
    return ix1, iy1, ix2, iy2


def grid_cells(bounds: tuple[int, int, int, int], first: int, last: int, n: int = 5) -> tuple[int, int, int, int]:
    """Pixel bounds of cells first..last (inclusive, both axes) of an n x n split of a box."""
    x1, y1, x2, y2 = bounds
    xs = np.linspace(x1, x2, n + 1)
    ys = np.linspace(y1, y2, n + 1)
    cx1, cx2 = int(np.floor(xs[first])), int(np.ceil(xs[last + 1]))
    cy1, cy2 = int(np.floor(ys[first])), int(np.ceil(ys[last + 1]))
    return cx1, cy1, max(cx2, cx1 + 1), max(cy2, cy1 + 1)


def world_points(u: np.ndarray, v: np.ndarray, d: np.ndarray, K: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Eq. 8: p'' = T D(p) K^-1 p: pixels (u, v) with depth d (metres) -> Nx3 world points, with
    T the frame's camera-to-world pose (the paper's "relative to the first keyframe" is the
    world frame of the sequence's poses here)."""
    x = (u - K[0, 2]) / K[0, 0] * d
    y = (v - K[1, 2]) / K[1, 1] * d
    cam = np.stack([x, y, d], axis=-1).reshape(-1, 3)
    return cam @ pose[:3, :3].T + pose[:3, 3]


def _region_pixels(depth: np.ndarray, bounds: tuple[int, int, int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x1, y1, x2, y2 = bounds
    region = depth[y1:y2, x1:x2]
    v, u = np.nonzero(region > 0)
    return (u + x1).astype(np.float64), (v + y1).astype(np.float64), region[v, u].astype(np.float64)


def _drop_depth_outliers(d: np.ndarray) -> np.ndarray:
    med = np.median(d)
    spread = 1.4826 * np.median(np.abs(d - med))
    return np.abs(d - med) <= max(0.10, 3.0 * spread)


@dataclass(frozen=True)
class PositionGaussian:
    mean: tuple[float, float, float]
    var: tuple[float, float, float]
    n_points: int
    region: str               # "centre cell" or "centre 3x3"
    median_depth: float       # of the region, metres (the object's distance from the camera)


def position_gaussian(frame: Frame, box: Box, min_points: int = MIN_CENTRE_POINTS) -> Optional[PositionGaussian]:
    """The object's 3-D position as a per-axis Gaussian over its centre region (Eq. 8)."""
    w, h = frame.size
    bounds = clip_box(box, w, h)
    depth = frame.depth
    for region, (first, last) in (("centre cell", (2, 2)), ("centre 3x3", (1, 3))):
        u, v, d = _region_pixels(depth, grid_cells(bounds, first, last))
        if d.size >= min_points:
            break
    if d.size == 0:
        return None
    keep = _drop_depth_outliers(d)
    pts = world_points(u[keep], v[keep], d[keep], frame.K, frame.pose)
    return PositionGaussian(vec3(pts.mean(axis=0)), vec3(pts.var(axis=0)),
                            int(len(pts)), region, float(np.median(d[keep])))


def sample_stride(bounds: tuple[int, int, int, int], max_samples: int = MAX_BOX_SAMPLES) -> int:
    """Pixel step that keeps a box's sampled grid at about max_samples pixels."""
    x1, y1, x2, y2 = bounds
    return max(1, int(np.ceil(np.sqrt((x2 - x1) * (y2 - y1) / max_samples))))


def object_mask(depth: np.ndarray, bounds: tuple[int, int, int, int], stride: int = 1,
                leave_out: Optional[np.ndarray] = None) -> np.ndarray:
    """Pixels of the box (bool, on the box's grid sampled every `stride` pixels) on the depth
    surface connected to its centre 3x3; pixels of `leave_out` (same grid: the floor) are neither
    part of it nor a bridge to another surface."""
    x1, y1, x2, y2 = bounds
    crop = depth[y1:y2:stride, x1:x2:stride]
    valid = crop > 0
    if leave_out is not None:
        valid = valid & ~leave_out
    tol = np.maximum(DEPTH_JUMP_M, DEPTH_JUMP_REL * crop)
    jump = np.zeros_like(valid)
    dx = np.abs(np.diff(crop, axis=1)) > tol[:, 1:]
    dy = np.abs(np.diff(crop, axis=0)) > tol[1:, :]
    # cut on the far side of each jump: the nearer surface keeps its border pixels
    far_x = crop[:, 1:] > crop[:, :-1]
    jump[:, 1:] |= dx & far_x
    jump[:, :-1] |= dx & ~far_x
    far_y = crop[1:, :] > crop[:-1, :]
    jump[1:, :] |= dy & far_y
    jump[:-1, :] |= dy & ~far_y
    n, labels = cv2.connectedComponents((valid & ~jump).astype(np.uint8), connectivity=4)
    cx1, cy1, cx2, cy2 = grid_cells((0, 0, crop.shape[1], crop.shape[0]), 1, 3)
    centre = labels[cy1:cy2, cx1:cx2]
    counts = np.bincount(centre[centre > 0].ravel(), minlength=n)
    if n <= 1 or counts.max() == 0:
        return valid
    return labels == int(np.argmax(counts))


def floor_pixels(depth_crop: np.ndarray, bounds: tuple[int, int, int, int], stride: int, frame: Frame,
                 ground: Ground, band: float = FLOOR_BAND_M) -> np.ndarray:
    """Pixels of a box's sampled grid (`depth_crop` = depth[y1:y2:stride, x1:x2:stride] of `frame`)
    whose point lies within `band` of the floor's height (`ground.floor` = p . up of the floor
    plane, the build's gravity estimate): the floor seen around and under a chair's legs or through
    its open base is no part of it, and no bridge to the wall it stands against."""
    K, pose, up, floor = frame.K, frame.pose, ground.up, ground.floor
    assert floor is not None
    x1, y1 = bounds[0], bounds[1]
    h, w = depth_crop.shape
    v, u = np.mgrid[0:h, 0:w]
    pts = world_points((u * stride + x1).astype(np.float64), (v * stride + y1).astype(np.float64),
                       depth_crop.astype(np.float64), K, pose)
    heights = (pts @ np.asarray(up, dtype=np.float64)).reshape(h, w)
    return (depth_crop > 0) & (heights < floor + band)


def object_box(frame: Frame, box: Box, up: Optional[ArrayLike] = None,
               lo: float = BOX_LOW_PERCENTILE, hi: float = BOX_HIGH_PERCENTILE,
               floor: Optional[float] = None) -> Optional[tuple[tuple[float, float, float], tuple[float, float, float]]]:
    """The object's 3-D box in the gravity frame: (centre in world coordinates, (width, depth,
    height) in metres along (e1, e2, up) of horizontal_basis(up)); None without depth.

    Percentiles of the points on the depth surface connected to the box centre, so background
    seen around the object and flying pixels at its border do not inflate it. With the floor's
    height `floor` (p . up), the floor's pixels (`floor_pixels`) are left out first, unless that
    leaves under MIN_OFF_FLOOR_SHARE of the box's depth (a thing lying flat on the floor is its
    own floor level). `up` defaults to the camera's image-up direction (-y_cam) in world
    coordinates.
    """
    w, h = frame.size
    bounds = clip_box(box, w, h)
    stride = sample_stride(bounds)
    leave_out = None
    if floor is not None and up is not None:
        x1, y1, x2, y2 = bounds
        crop = frame.depth[y1:y2:stride, x1:x2:stride]
        on_floor = floor_pixels(crop, bounds, stride, frame, Ground(up, floor))
        if np.count_nonzero((crop > 0) & ~on_floor) >= MIN_OFF_FLOOR_SHARE * np.count_nonzero(crop > 0):
            leave_out = on_floor
    mask = object_mask(frame.depth, bounds, stride, leave_out)
    v, u = np.nonzero(mask)
    if u.size < 3:
        return None
    x1, y1 = bounds[0], bounds[1]
    u, v = u * stride, v * stride
    d = frame.depth[v + y1, u + x1].astype(np.float64)
    valid = d > 0
    if valid.sum() < 3:
        return None
    u, v, d = u[valid], v[valid], d[valid]
    pts = world_points((u + x1).astype(np.float64), (v + y1).astype(np.float64), d, frame.K, frame.pose)
    if up is None:
        up = -frame.pose[:3, 1]
    R = horizontal_frame(up)
    local = pts @ R.T
    low, high = np.percentile(local, lo, axis=0), np.percentile(local, hi, axis=0)
    centre = R.T @ ((low + high) / 2)
    return vec3(centre), vec3(high - low)


def object_size(frame: Frame, box: Box, up: Optional[Sequence[float]] = None,
                lo: float = BOX_LOW_PERCENTILE, hi: float = BOX_HIGH_PERCENTILE) -> Optional[tuple[float, float, float]]:
    """(width, depth, height) in metres along (e1, e2, up); None without depth (see object_box)."""
    found = object_box(frame, box, up, lo, hi)
    return None if found is None else found[1]


def hsv_histogram(image: np.ndarray, box: Optional[Box] = None, bins: int = HIST_BINS) -> np.ndarray:
    """Eq. 9: h_{H,S,V} = N Pr(H = h, S = s, V = v) over the box's pixels, bins^3 counts (float64,
    H-major: index = (h * bins + s) * bins + v); sums to N, the number of pixels."""
    if box is not None:
        x1, y1, x2, y2 = clip_box(box, image.shape[1], image.shape[0])
        image = image[y1:y2, x1:x2]
    hsv = cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_BGR2HSV)
    hist = cv2.calcHist([hsv], [0, 1, 2], None, [bins, bins, bins], [0, 180, 0, 256, 0, 256])
    return hist.reshape(-1).astype(np.float64)


# A box's colour is read from its inner region (this margin cut on every side: the corners of a
# box around a rounded object are background) where depth shows the object's surface...
INNER_MARGIN = 0.2
# ... and from the whole inner region when that surface covers under this share of it.
MIN_MASK_SHARE = 0.25
# The object's own depths lie within half its box's metric width, at least this, of its centre's.
MIN_DEPTH_BAND = 0.05
# A whole frame's cast is estimated on its pixels sampled every this many pixels.
CAST_STRIDE = 16


def colour_pixels(frame: Frame, bounds: tuple[int, int, int, int], screen: bool = False) -> tuple[np.ndarray, int]:
    """(BGR pixels N x 3, their sampling stride) that show the object in a box: the samples of
    the box's inner region (INNER_MARGIN) on the surface `object_mask` connects to the centre and
    at the object's own depth (`within_object_depth`), or the whole inner region when those are
    under MIN_MASK_SHARE of it (black and glossy surfaces return little depth). A screen's box is
    read whole: its frame lies at the box's edge and its glass returns little depth."""
    stride = sample_stride(bounds)
    x1, y1, x2, y2 = bounds
    crop = frame.color[y1:y2:stride, x1:x2:stride]
    if screen:
        return crop.reshape(-1, 3), stride
    h, w = crop.shape[:2]
    my, mx = int(h * INNER_MARGIN), int(w * INNER_MARGIN)
    inner = np.zeros((h, w), bool)
    inner[my:max(h - my, my + 1), mx:max(w - mx, mx + 1)] = True
    mask = object_mask(frame.depth, bounds, stride) & inner
    mask &= within_object_depth(frame.depth[y1:y2:stride, x1:x2:stride], bounds, frame.K)
    if mask.sum() >= max(3, MIN_MASK_SHARE * inner.sum()):
        return crop[mask], stride
    return crop[inner], stride


def within_object_depth(depth_crop: np.ndarray, bounds: tuple[int, int, int, int], K: np.ndarray) -> np.ndarray:
    """Pixels of a box whose depth lies within half the box's metric width of the median depth
    of its centre 3x3 cells: an object is about as deep as it is wide, so what lies further
    (the table behind a cup, the wall behind a chair) is another surface."""
    cx1, cy1, cx2, cy2 = grid_cells((0, 0, depth_crop.shape[1], depth_crop.shape[0]), 1, 3)
    centre = depth_crop[cy1:cy2, cx1:cx2]
    centre = centre[centre > 0]
    if centre.size == 0:
        return depth_crop > 0
    d0 = float(np.median(centre))
    band = max(MIN_DEPTH_BAND, 0.5 * (bounds[2] - bounds[0]) / K[0, 0] * d0)
    return (depth_crop > 0) & (np.abs(depth_crop - d0) <= band)


def object_colour(frame: Frame, box: Box, label: Optional[str] = None,
                  screens: Sequence[Box] = ()) -> tuple[colour_model.ColourReading, float]:
    """(colour reading, view weight) of a boxed object in one frame: its own pixels
    (`colour_pixels`) read with the cast of the light on it (`sg3d.ingest.objects.colour.surround_cast`,
    the boxes of the frame's `screens` left out of its surround) divided out, as a
    screen when `label` is one; the weight from the pixels' area, the crop's sharpness and
    whether the box touches the image border."""
    w, h = frame.size
    bounds = clip_box(box, w, h)
    screen = colour_model.is_screen(label)
    pixels, stride = colour_pixels(frame, bounds, screen)
    cast = colour_model.surround_cast(frame.color, bounds, emitters=[clip_box(b, w, h) for b in screens])
    reading = colour_model.read_colour(pixels, cast, screen=screen)
    x1, y1, x2, y2 = bounds
    grey = frame.gray[y1:y2:stride, x1:x2:stride]
    sharpness = float(cv2.Laplacian(grey, cv2.CV_32F).var()) if min(grey.shape) >= 3 else 0.0
    return reading, colour_model.view_weight(len(pixels) * stride * stride, sharpness, cut_at_border(bounds, w, h))


def cut_at_border(bounds: tuple[int, int, int, int], width: int, height: int) -> bool:
    """Whether a clipped box (x1, y1, x2, y2) touches the image border (within a pixel): the
    object may go on beyond the image, so the box shows only part of it."""
    x1, y1, x2, y2 = bounds
    return x1 <= 1 or y1 <= 1 or x2 >= width - 1 or y2 >= height - 1


def dominant_colour(image: np.ndarray, box: Optional[Box] = None, margin: float = INNER_MARGIN) -> str:
    """The colour of the box's inner region (`margin` cut on every side) of an image without
    depth, named by `sg3d.ingest.objects.colour.read_colour` as it is (no cast estimate from one crop)."""
    x1, y1, x2, y2 = clip_box(box if box is not None else (0, 0, image.shape[1], image.shape[0]),
                              image.shape[1], image.shape[0])
    mx, my = int((x2 - x1) * margin), int((y2 - y1) * margin)
    inner = image[y1 + my:max(y2 - my, y1 + my + 1), x1 + mx:max(x2 - mx, x1 + mx + 1)]
    return colour_model.read_colour(inner.reshape(-1, 3)).name


def thumbnail(image: np.ndarray, box: Optional[Box] = None, max_side: int = THUMBNAIL_SIDE,
              quality: int = 85) -> bytes:
    """JPEG bytes of the box, scaled down so its longest side is at most max_side."""
    if box is not None:
        x1, y1, x2, y2 = clip_box(box, image.shape[1], image.shape[0])
        image = image[y1:y2, x1:x2]
    h, w = image.shape[:2]
    scale = min(1.0, max_side / max(h, w))
    if scale < 1.0:
        image = cv2.resize(image, (max(1, round(w * scale)), max(1, round(h * scale))), interpolation=cv2.INTER_AREA)
    ok, buf = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, quality])
    if not ok:
        raise ValueError("JPEG encoding failed")
    return buf.tobytes()


@dataclass(frozen=True)
class ObjectAttributes:
    """What one frame tells about one boxed object: the fields of ObjectObservation but labels."""

    mean: tuple[float, float, float]
    var: tuple[float, float, float]
    n_points: int
    size: tuple[float, float, float]
    hist: np.ndarray
    colour: str
    thumbnail: bytes
    centre: tuple[float, float, float]   # centre of the 3-D box (mean is the centre patch's)
    colour_reading: Optional[colour_model.ColourReading] = None   # None: only `colour` is known
    view_weight: float = 1.0             # how well this view shows the object's colour
    cut: bool = False                    # the box touches the image border (`cut_at_border`)


def measure_object(frame: Frame, box: Box, up: Optional[Sequence[float]] = None,
                   label: Optional[str] = None, screens: Sequence[Box] = (),
                   floor: Optional[float] = None) -> Optional[ObjectAttributes]:
    """All attributes of a boxed object (detected as `label`, if given) in a frame whose
    detected screens have boxes `screens`, its box measured off the floor at height `floor`
    (`object_box`); None when the box has no usable depth."""
    pos = position_gaussian(frame, box)
    if pos is None:
        return None
    centre, size = object_box(frame, box, up, floor=floor) or (pos.mean, (0.0, 0.0, 0.0))
    image = frame.color
    reading, weight = object_colour(frame, box, label, screens)
    cut = cut_at_border(clip_box(box, *frame.size), *frame.size)
    return ObjectAttributes(pos.mean, pos.var, pos.n_points, size, hsv_histogram(image, box),
                            reading.name, thumbnail(image, box), centre, reading, weight, cut)
