"""Flat things lying on a top (1-5 cm tall: a keyboard, a phone, papers, a book lying flat), per view.

The fused cloud spreads a top's points over about +-1 cm (pose and gravity error), so what lies
within `structure.SURFACE_SLAB_M` of a top's level is taken as the top and a 2 cm keyboard goes
with it. One view's own depth does not suffer that spread: the top is a plane in it to within
the sensor's noise. So, for each horizontal surface (`structure.Element` with a footprint: a
desk's, a table's, a counter's top):

- `top_views`: the views that see the top well (many of their pixels on its footprint at its level);
- `view_plane`: the top's plane fitted in that view's own depth (trimmed least squares);
- `lying_pixels`: in that view, the pixels over the top's footprint that rise out of that plane
  by more than the sensor's noise allows (`rise_threshold`), or differ in colour from the top's
  own dominant colour (`colour_distance` >= CONTRAST_DELTA_E) without lying under the plane, and no
  higher than a flat thing (FLAT_MAX_RISE_M); pixels beside a depth jump (flying pixels) are left out;
- `fused_cells`: a cell of the top counts as lying when at least MIN_LYING_VIEWS of the views that
  saw it, and LYING_SHARE of them, found it lying (one view's glare, blur or noise is outvoted);
- `flat_regions`: connected regions of such cells (OpenCV morphology and connected components),
  away from what stands taller (TALL_CLEARANCE_M) and from the things already found (`taken`),
  footprints between MIN_FLAT_SIDE_M and MAX_FLAT_SIDE_M, each an unnamed flat segment lying ON
  the top (its bottom at the top's level, its height the median rise measured in the views).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Optional, Sequence

import cv2
import numpy as np
from scipy import ndimage

from sg3d.ingest.discover.room_cloud import NORMAL_JUMP_M, NORMAL_JUMP_REL, RoomCloud, grid_points
from sg3d.ingest.discover.segments import Segment
from sg3d.ingest.discover.structure import SURFACE_CELL_M, SURFACE_SLAB_M, UP_NORMAL_COS, Element
from sg3d.ingest.objects import colour as colour_model

if TYPE_CHECKING:
    from sg3d.ingest.objects.existence import View

# Axial depth noise of a structured-light / stereo RGB-D camera (Kinect v1 model, Nguyen et al.
# 2012, which the RealSense D4xx roughly follows at desk range): sigma(z) = NOISE_A + NOISE_B (z - NOISE_Z0)^2.
NOISE_A_M = 0.0012
NOISE_B_PER_M = 0.0019
NOISE_Z0_M = 0.4
# A pixel rises out of its view's plane when it stands RISE_SIGMAS noise widths above it (a false
# rise then has odds under 1 in 3000 per pixel), and never less than RISE_MIN_M: depth is stored
# in whole millimetres and the plane itself is fitted to +-1-2 mm; a thing 1 cm thick still clears it.
RISE_SIGMAS = 3.5
RISE_MIN_M = 0.006
# The plane's inliers: within PLANE_INLIER_SIGMAS noise widths of the fit (trimmed in
# PLANE_ITERATIONS rounds; a flat thing covering part of the top is trimmed away).
PLANE_INLIER_SIGMAS = 3.0
PLANE_ITERATIONS = 3
# The top's plane in a view is found among RANSAC_SAMPLES three-point planes (with 30 % of the band's
# points on a thing, one in 3 draws is all top: 64 draws miss it with odds ~1e-11); a plane with
# LOWER_PLANE_SHARE of the best one's inliers that lies lower is the top (things lie on it).
RANSAC_SAMPLES = 64
LOWER_PLANE_SHARE = 0.5
# In one view the top tilts as the fused top does (the room's gravity error, common to all views)
# and by that view's own pose error (the fused top's +-1 cm over a metre: about 1 degree); a plane
# tilted more than MAX_TILT_DEG from the fused top's runs across things.
MAX_TILT_DEG = 2.0
FUSED_ITERATIONS = 2
# A flat thing is at most this high above the top (the 1-5 cm, with a centimetre for the
# plane and the noise); what rises higher is a taller thing the voxel segments find.
FLAT_MAX_RISE_M = 0.06
# Colour contrast against the top's dominant colour: CIE76 distance with lightness weighted by
# LIGHTNESS_WEIGHT (the CMC 2:1 acceptability weighting: shading and light falloff across one top
# move lightness far more than hue). Two surfaces are plainly different past CONTRAST_DELTA_E
# (10 is a large difference at a glance; JPEG and sensor colour noise are a few units); grey
# paper on a black desk or a red keyboard on it lie far past it.
LIGHTNESS_WEIGHT = 0.5
CONTRAST_DELTA_E = 18.0
# A top is seen well by a view with at least MIN_TOP_PIXELS pixels of its small depth grid on the
# top's footprint at its level (a 15 x 15 cm patch at 0.6 m); the MAX_TOP_VIEWS best are used.
MIN_TOP_PIXELS = 200
MAX_TOP_VIEWS = 16
# Fusion on the top: FLAT_CELL_M cells (about one small-depth pixel at desk range); a cell is lying
# when MIN_LYING_VIEWS views and LYING_SHARE of the views that saw it found it lying.
FLAT_CELL_M = 0.015
MIN_LYING_VIEWS = 3
LYING_SHARE = 0.5
# A region within TALL_CLEARANCE_M of what rises higher than a flat thing is that thing's foot
# (its side's lowest pixels, flying pixels at its base), not a flat thing.
TALL_CLEARANCE_M = 0.03
# Flat things: each horizontal side at least MIN_FLAT_SIDE_M (a phone's width, less a cell),
# the longer at most MAX_FLAT_SIDE_M (a newspaper open, a laptop closed), at least MIN_FLAT_AREA_M2.
MIN_FLAT_SIDE_M = 0.05
MAX_FLAT_SIDE_M = 0.70
MIN_FLAT_AREA_M2 = 0.004
# A region is already found when this share of its cells lies inside a taken box (grown by a cell)
# standing on the top; a box over TOP_SHARE of the top's footprint is the top's own furniture.
TAKEN_SHARE = 0.3
TOP_SHARE = 0.5
# A flat thing's extent: its lying pixels from this percentile to 100 less it (the extremes are
# mixed pixels at its rim).
EXTENT_PERCENTILE = 1.0
# The height stored for a flat thing is at least a depth quantum above the top.
MIN_HEIGHT_M = 0.005


def depth_noise(z: np.ndarray) -> np.ndarray:
    """Rule "sensor noise": the axial depth noise sigma(z) = NOISE_A_M + NOISE_B_PER_M (z -
    NOISE_Z0_M)^2 of a structured-light or stereo RGB-D camera at range z (metres)."""
    return NOISE_A_M + NOISE_B_PER_M * (np.asarray(z, float) - NOISE_Z0_M) ** 2


def rise_threshold(z: np.ndarray) -> np.ndarray:
    """Rule "it rises": a pixel at range z stands out of its view's plane when it lies at least
    RISE_SIGMAS noise widths (`depth_noise`) above it, and at least RISE_MIN_M."""
    return np.maximum(RISE_MIN_M, RISE_SIGMAS * depth_noise(z))


def colour_distance(lab: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Rule "another colour": the CIE76 distance of CIELAB pixels from a reference colour with
    lightness weighted by LIGHTNESS_WEIGHT (shading moves lightness across one surface)."""
    d = np.asarray(lab, float) - np.asarray(reference, float)
    return np.sqrt((LIGHTNESS_WEIGHT * d[..., 0]) ** 2 + d[..., 1] ** 2 + d[..., 2] ** 2)


@dataclass
class ViewGrid:
    """One view's small depth grid in the gravity frame: points (H x W x 3, NaN where no depth),
    range z; the pixels beside a depth jump (`depth_jumps`) and
    those whose surface faces up (`faces_up`) worked out when first asked (for the views that see a top)."""

    k: int
    points: np.ndarray
    z: np.ndarray

    @functools.cached_property
    def jump(self) -> np.ndarray:
        return depth_jumps(self.z)

    @functools.cached_property
    def up(self) -> np.ndarray:
        return faces_up(self.points)


def view_grid(k: int, cloud: RoomCloud) -> ViewGrid:
    """The gravity-frame points of view k's small depth grid (`room_cloud.grid_points`)."""
    pts, d = grid_points(cloud.views[k], cloud.basis, cloud.floor)
    valid = d > 0
    return ViewGrid(k, np.where(valid[..., None], pts, np.nan), d)


def depth_jumps(d: np.ndarray) -> np.ndarray:
    """The pixels of a depth grid (0 = none) next to a depth jump larger than the normals'
    (room_cloud: NORMAL_JUMP_REL * z + NORMAL_JUMP_M), grown by a pixel: flying pixels between a
    thing and what lies behind it. A hole is no jump: depth is missing there, not far."""
    valid = d > 0
    far = np.zeros_like(valid)
    tol = NORMAL_JUMP_REL * d + NORMAL_JUMP_M
    across = (np.abs(np.diff(d, axis=1)) > np.minimum(tol[:, 1:], tol[:, :-1])) & valid[:, 1:] & valid[:, :-1]
    far[:, 1:] |= across
    far[:, :-1] |= across
    down = (np.abs(np.diff(d, axis=0)) > np.minimum(tol[1:], tol[:-1])) & valid[1:] & valid[:-1]
    far[1:] |= down
    far[:-1] |= down
    return cv2.dilate(far.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)


def faces_up(pts: np.ndarray) -> np.ndarray:
    """Rule "lying flat shows a face up": the pixels of a gravity-frame grid (H x W x 3, NaN where
    no depth) whose normal (the cross product of the differences of their neighbours across and
    down) lies within the up-facing cone of `structure.UP_NORMAL_COS`, or is unknown (a neighbour
    without depth), off the image's outer pixels. A wall's foot or a cup's side behind a top faces sideways."""
    n = np.cross(pts[1:-1, 2:] - pts[1:-1, :-2], pts[2:, 1:-1] - pts[:-2, 1:-1])
    norm = np.linalg.norm(n, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.abs(n[..., 2]) / norm
    out = np.zeros(pts.shape[:2], bool)               # the image's rim: a thing cut there shows no face
    out[1:-1, 1:-1] = ~(cos < UP_NORMAL_COS)          # NaN (unknown) stays up
    return out


def grown_footprint(el: Element) -> np.ndarray:
    """The top's footprint grown by one of its cells all round (its edge cells were seen by fewer
    views: a phone at the edge of a desk); cell [0, 0] lies one cell before `el.origin`."""
    assert el.footprint is not None
    return ndimage.binary_dilation(np.pad(el.footprint, 1))


def over_top(el: Element, pts: np.ndarray, grown: Optional[np.ndarray] = None) -> np.ndarray:
    """Mask of the points (... x 3, NaN allowed) whose (a, b) lie over the top's grown footprint
    (`grown_footprint`, computed when not given)."""
    assert el.origin is not None
    fp = grown_footprint(el) if grown is None else grown
    start = el.origin - SURFACE_CELL_M
    with np.errstate(invalid="ignore"):
        near = ((pts[..., 0] >= start[0]) & (pts[..., 1] >= start[1])
                & (pts[..., 0] < start[0] + fp.shape[0] * SURFACE_CELL_M)
                & (pts[..., 1] < start[1] + fp.shape[1] * SURFACE_CELL_M))
    out = np.zeros(near.shape, bool)
    cells = np.floor((pts[near][:, :2] - start) / SURFACE_CELL_M).astype(np.int64)
    cells = np.minimum(cells, np.array(fp.shape) - 1)
    out[near] = fp[cells[:, 0], cells[:, 1]]
    return out


def top_points(el: Element, cloud: RoomCloud) -> np.ndarray:
    """Indices of the cloud's points over the top's grown footprint (`over_top`) within
    3 SURFACE_SLAB_M of its level: where its plane is looked for."""
    p = cloud.points
    lo, hi = el.lo[:2] - SURFACE_CELL_M, el.hi[:2] + SURFACE_CELL_M
    idx = np.flatnonzero((np.abs(p[:, 2] - el.height) <= 3 * SURFACE_SLAB_M) & (p[:, 0] >= lo[0]) & (p[:, 0] <= hi[0])
                         & (p[:, 1] >= lo[1]) & (p[:, 1] <= hi[1]))
    return idx[over_top(el, p[idx])]


def fused_plane(el: Element, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The top's plane h = c0 a + c1 b + c2 in the fused cloud (`pts`: its `top_points`): least
    squares over those within SURFACE_SLAB_M of its level, then again FUSED_ITERATIONS times
    within SURFACE_SLAB_M of the plane fitted (a top tilted in the gravity frame leaves the
    level's slab at its ends: cut so, it fits too level); level at its height when too few
    points. Returns the plane and the mask of the points within SURFACE_SLAB_M of it."""
    coef = np.array([0.0, 0.0, el.height])
    near = np.abs(pts[:, 2] - el.height) <= SURFACE_SLAB_M
    for _ in range(FUSED_ITERATIONS + 1):
        if int(near.sum()) < MIN_TOP_PIXELS:
            break
        coef = np.linalg.lstsq(np.c_[pts[near, :2], np.ones(int(near.sum()))], pts[near, 2], rcond=None)[0]
        near = np.abs(pts[:, 2] - plane_height(coef, pts)) <= SURFACE_SLAB_M
    return coef, near


def plane_height(plane: np.ndarray, ab: np.ndarray) -> np.ndarray:
    """The height of a plane h = c0 a + c1 b + c2 at points (..., >= 2) (NaN allowed)."""
    return ab[..., 0] * plane[0] + ab[..., 1] * plane[1] + plane[2]


def top_views(frames: np.ndarray, n_views: int) -> list[int]:
    """Rule "seen well": the views (positions) with at least MIN_TOP_PIXELS of their small-grid
    points on the top (`frames`: the view of each of the top's fused points within
    SURFACE_SLAB_M of its plane), most first, at most MAX_TOP_VIEWS."""
    counts = np.bincount(frames, minlength=n_views)
    ranked = sorted((int(-c), k) for k, c in enumerate(counts) if c >= MIN_TOP_PIXELS)
    return [k for _, k in ranked[:MAX_TOP_VIEWS]]


def plane_hypotheses(pts: np.ndarray, z: np.ndarray, tilt: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """RANSAC_SAMPLES planes h = c0 a + c1 b + c2 through three points each (drawn by a generator
    seeded from the point count: the same view gives the same planes) whose slope (c0, c1) lies within
    MAX_TILT_DEG of `tilt` (the fused top's), each with its inliers: the points within PLANE_INLIER_SIGMAS noise widths (`depth_noise`)."""
    rng = np.random.default_rng(len(pts))
    tol = PLANE_INLIER_SIGMAS * depth_noise(z)
    out = []
    for trio in rng.integers(0, len(pts), size=(RANSAC_SAMPLES, 3)):
        A = np.c_[pts[trio, :2], np.ones(3)]
        if abs(np.linalg.det(A)) < 1e-6:
            continue
        coef = np.linalg.solve(A, pts[trio, 2])
        if not level_with(coef, tilt):
            continue
        out.append((coef, np.abs(pts[:, 2] - (pts[:, :2] @ coef[:2] + coef[2])) <= tol))
    return out


def view_plane(pts: np.ndarray, z: np.ndarray, tilt: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """Rule "the top in this view's own depth": of the planes through the view's points of the
    top (N x 3, ranges z; `plane_hypotheses`) holding at least LOWER_PLANE_SHARE of the best one's
    inliers, the lowest at the points' centre (things lie ON a top: a keyboard covering as much
    of a black desk as depth sees of the desk is a plane too, but above it), refitted by least
    squares to its inliers PLANE_ITERATIONS times. Returns (coefficients, inlier mask), or None
    with fewer than MIN_TOP_PIXELS inliers or a fit no longer level with the fused top (`level_with`)."""
    if len(pts) < MIN_TOP_PIXELS:
        return None
    planes = plane_hypotheses(pts, z, tilt)
    if not planes:
        return None
    best = max(int(keep.sum()) for _, keep in planes)
    centre = np.r_[pts[:, :2].mean(axis=0), 1.0]
    coef, keep = min(((c, k) for c, k in planes if k.sum() >= LOWER_PLANE_SHARE * best),
                     key=lambda ck: float(centre @ ck[0]))
    for _ in range(PLANE_ITERATIONS):
        if int(keep.sum()) < MIN_TOP_PIXELS:
            return None
        A = np.c_[pts[keep, :2], np.ones(int(keep.sum()))]
        coef = np.linalg.lstsq(A, pts[keep, 2], rcond=None)[0]
        keep = np.abs(pts[:, 2] - (pts[:, :2] @ coef[:2] + coef[2])) <= PLANE_INLIER_SIGMAS * depth_noise(z)
    if int(keep.sum()) < MIN_TOP_PIXELS or not level_with(coef, tilt):
        return None
    return coef, keep


def level_with(coef: np.ndarray, tilt: np.ndarray) -> bool:
    """A plane's slope (c0, c1) lies within MAX_TILT_DEG of `tilt` (the fused top's)."""
    return float(np.hypot(coef[0] - tilt[0], coef[1] - tilt[1])) <= np.tan(np.radians(MAX_TILT_DEG))


def small_lab(image: Optional[np.ndarray], shape: tuple[int, int]) -> Optional[np.ndarray]:
    """A colour image (BGR) brought to the small depth grid's shape (area average: the colour each
    depth pixel covers) in CIELAB (`colour.bgr_to_lab`)."""
    if image is None:
        return None
    small = cv2.resize(image, (shape[1], shape[0]), interpolation=cv2.INTER_AREA)
    return colour_model.bgr_to_lab(small.reshape(-1, 3)).reshape(shape[0], shape[1], 3)


@dataclass
class Lying:
    """One view's verdict on a top: its pixels over the top that lie on it (a flat thing), that rise
    higher (a taller thing), that it saw at all, and each pixel's rise out of the view's plane."""

    lying: np.ndarray
    tall: np.ndarray
    seen: np.ndarray
    rise: np.ndarray


def lying_pixels(plane: np.ndarray, g: ViewGrid, over: np.ndarray, lab: Optional[np.ndarray]) -> Optional[Lying]:
    """Rule "lying on the top, in one view": the top's plane in this view's depth (`view_plane`
    on its pixels over the footprint within SURFACE_SLAB_M of the fused `plane`, off depth jumps); a
    pixel over the footprint lies on the top when it rises out of the plane (`rise_threshold`) or
    differs from the top's own colour (the median CIELAB of the plane's inliers) by
    CONTRAST_DELTA_E (`colour_distance`) without lying under the plane, at most FLAT_MAX_RISE_M
    high, not beside a depth jump and facing up (`faces_up`; one view's specks are outvoted in `lying_cells`). Pixels rising
    higher are a taller thing's. None when the view holds no plane of the top."""
    h = np.nan_to_num(g.points[..., 2], nan=-1e6)
    band = over & ~g.jump & (np.abs(np.nan_to_num(h - plane_height(plane, g.points), nan=1e6)) <= SURFACE_SLAB_M)
    fit = view_plane(g.points[band], g.z[band], plane[:2])
    if fit is None:
        return None
    coef, inliers = fit
    ab = np.nan_to_num(g.points[..., :2])
    rise = np.where(over, h - (ab @ coef[:2] + coef[2]), np.nan)
    r = np.nan_to_num(rise, nan=-1e6)
    noise = depth_noise(g.z)
    flat = over & ~g.jump & g.up & (r <= FLAT_MAX_RISE_M) & (r >= -PLANE_INLIER_SIGMAS * noise)
    lying = flat & (r >= rise_threshold(g.z))
    if lab is not None:
        top = np.median(lab[band][inliers], axis=0)
        lying |= flat & (colour_distance(lab, top) >= CONTRAST_DELTA_E)
    return Lying(lying, over & (r > FLAT_MAX_RISE_M), flat, rise)


@dataclass
class TopCells:
    """Votes of the views on a top's FLAT_CELL_M cells, and the lying pixels they came from."""

    origin: np.ndarray            # (a, b) of cell [0, 0]
    seen: np.ndarray              # views that saw the cell (flat or lying)
    lying: np.ndarray             # views that found it lying
    tall: np.ndarray              # views that saw something taller there
    points: np.ndarray            # N x 5 lying pixels: a, b, rise, view position, pixel footprint (m)
    views: dict                   # view position -> lying cells it saw (flat index -> count)


def _cell_index(ab: np.ndarray, origin: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Flat index of each (a, b)'s FLAT_CELL_M cell in a grid of `shape` at `origin`; -1 outside."""
    ij = np.floor((ab - origin) / FLAT_CELL_M).astype(np.int64)
    ok = (ij[:, 0] >= 0) & (ij[:, 1] >= 0) & (ij[:, 0] < shape[0]) & (ij[:, 1] < shape[1])
    return np.where(ok, ij[:, 0] * shape[1] + ij[:, 1], -1)


def splat(idx: np.ndarray, shape: tuple[int, int], pixel_m: float) -> np.ndarray:
    """The cells (flat indices, -1 outside) a view's pixels cover: each pixel's cell grown to the
    pixel's footprint on the top (`pixel_m` across): a pixel wider than a cell leaves cells
    between its neighbours' centres, which it saw all the same."""
    marks = np.zeros(shape[0] * shape[1], np.uint8)
    marks[idx[idx >= 0]] = 1
    size = 2 * int(np.ceil((pixel_m / FLAT_CELL_M - 1) / 2)) + 1
    if size == 1:
        return marks.astype(bool)
    return np.asarray(cv2.dilate(marks.reshape(shape), np.ones((size, size), np.uint8)), bool).reshape(-1)


def fused_cells(el: Element, verdicts: Sequence[tuple[int, np.ndarray, Lying, float]]) -> TopCells:
    """Each view's verdict (view position, gravity points, `Lying`, pixel footprint in metres)
    counted once per FLAT_CELL_M cell of the top's box (`splat`): how many views saw the cell,
    found it lying, saw something taller."""
    origin = el.lo[:2] - SURFACE_CELL_M - FLAT_CELL_M
    extent = np.ceil((el.hi[:2] + SURFACE_CELL_M - origin) / FLAT_CELL_M) + 2
    shape = (int(extent[0]), int(extent[1]))
    n = shape[0] * shape[1]
    seen, lying, tall = (np.zeros(n, int) for _ in range(3))
    kept, views = [], {}
    for k, pts, v, pixel_m in verdicts:
        for mask, count in ((v.seen | v.lying, seen), (v.lying, lying), (v.tall, tall)):
            count += splat(_cell_index(pts[mask][:, :2], origin, shape), shape, pixel_m)
        idx = _cell_index(pts[v.lying][:, :2], origin, shape)
        views[k] = np.bincount(idx[idx >= 0], minlength=n)
        lying_n = int(v.lying.sum())
        kept.append(np.c_[pts[v.lying][:, :2], v.rise[v.lying], np.full(lying_n, k), np.full(lying_n, pixel_m)])
    points = np.concatenate(kept) if kept else np.zeros((0, 5))
    return TopCells(origin, seen.reshape(shape), lying.reshape(shape), tall.reshape(shape), points, views)


def lying_cells(cells: TopCells) -> np.ndarray:
    """Rule "seen lying from several views": a cell lies when at least MIN_LYING_VIEWS views and
    LYING_SHARE of those that saw it found it lying, and no taller thing stands within
    TALL_CLEARANCE_M (seen so by MIN_LYING_VIEWS views); closed and opened by a 3 x 3 square
    (a gap of one cell inside a thing, a speck of one cell on the top)."""
    lying = (cells.lying >= MIN_LYING_VIEWS) & (cells.lying >= LYING_SHARE * cells.seen)
    reach = int(np.ceil(TALL_CLEARANCE_M / FLAT_CELL_M))
    tall = cv2.dilate((cells.tall >= MIN_LYING_VIEWS).astype(np.uint8), np.ones((2 * reach + 1,) * 2, np.uint8))
    grid = (lying & ~tall.astype(bool)).astype(np.uint8)
    square = np.ones((3, 3), np.uint8)
    grid = cv2.morphologyEx(grid, cv2.MORPH_CLOSE, square)
    return cv2.morphologyEx(grid, cv2.MORPH_OPEN, square).astype(bool)


def flat_size(width: float, depth: float) -> bool:
    """Rule "a flat thing's footprint": both horizontal sides at least MIN_FLAT_SIDE_M, the longer
    at most MAX_FLAT_SIDE_M, the area at least MIN_FLAT_AREA_M2."""
    return (min(width, depth) >= MIN_FLAT_SIDE_M and max(width, depth) <= MAX_FLAT_SIDE_M
            and width * depth >= MIN_FLAT_AREA_M2)


def already_taken(member: np.ndarray, origin: np.ndarray, taken: Sequence[tuple[np.ndarray, np.ndarray]]) -> bool:
    """A region (its cells' (i, j)) is a thing already found when TAKEN_SHARE of its cells' centres
    lie inside one of the `taken` gravity boxes' footprints grown by a cell."""
    ab = origin + (member + 0.5) * FLAT_CELL_M
    for lo, hi in taken:
        inside = ((ab >= lo[:2] - FLAT_CELL_M) & (ab <= hi[:2] + FLAT_CELL_M)).all(axis=1)
        if float(inside.mean()) >= TAKEN_SHARE:
            return True
    return False


def region_segment(plane: np.ndarray, cells: TopCells, member: np.ndarray) -> Optional[Segment]:
    """A lying region (cells (i, j)) as a flat segment ON the top: its footprint the extent of its
    lying pixels (EXTENT_PERCENTILE in from each end, half a pixel out), its bottom on the top's fused plane at its centre, its height their median
    rise (at least MIN_HEIGHT_M); voxels on its upper face at its cells' centres; the views that
    found most of it lying first. None when the footprint is no flat thing's (`flat_size`)."""
    shape = cells.seen.shape
    flat = member[:, 0] * shape[1] + member[:, 1]
    idx = _cell_index(cells.points[:, :2], cells.origin, shape)
    pts = cells.points[np.isin(idx, flat)]
    if len(pts) < MIN_LYING_VIEWS:
        return None
    # its pixels' centres lie half a pixel inside its edges; the extreme EXTENT_PERCENTILE are
    # mixed pixels at its rim (its colour bled into the top's)
    pad = 0.5 * float(np.median(pts[:, 4]))
    a_lo = np.percentile(pts[:, :2], EXTENT_PERCENTILE, axis=0) - pad
    a_hi = np.percentile(pts[:, :2], 100 - EXTENT_PERCENTILE, axis=0) + pad
    if not flat_size(*(a_hi - a_lo)):
        return None
    height = max(MIN_HEIGHT_M, float(np.median(pts[:, 2])))
    level = float(plane_height(plane, (a_lo + a_hi) / 2))
    lo = np.array([a_lo[0], a_lo[1], level])
    hi = np.array([a_hi[0], a_hi[1], level + height])
    ab = cells.origin + (member + 0.5) * FLAT_CELL_M
    voxels = np.c_[ab, np.full(len(ab), level + height)]
    votes = sorted(((int(v[flat].sum()), -k) for k, v in cells.views.items() if v[flat].sum() > 0), reverse=True)
    order = [-k for _, k in votes]
    hits = int(cells.lying.reshape(-1)[flat].sum())
    seg = Segment(voxels, lo, hi, np.array(sorted(order)), hits=hits,
                  free=int(cells.seen.reshape(-1)[flat].sum()) - hits, seen_views=len(order),
                  looked_views=len(order), best_view=order[0], good_views=tuple(order[:3]))
    return seg


def flat_regions(plane: np.ndarray, cells: TopCells, taken: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[Segment]:
    """The connected regions (8-neighbourhood, `cv2.connectedComponents`) of a top's lying cells
    (`lying_cells`) that no `taken` box holds (`already_taken`), each a flat segment
    (`region_segment`) when its footprint is a flat thing's."""
    n, labels = cv2.connectedComponents(lying_cells(cells).astype(np.uint8), connectivity=8)
    out = []
    for c in range(1, n):
        member = np.argwhere(labels == c)
        if already_taken(member, cells.origin, taken):
            continue
        seg = region_segment(plane, cells, member)
        if seg is not None:
            out.append(seg)
    return out


def pixel_footprint(view: View, z: np.ndarray) -> float:
    """The width (m) one pixel of a view's small depth grid covers at the median range z of its
    pixels on a top (z / focal length of the small grid)."""
    fx = float(view.K[0, 0]) * view.depth.shape[1] / view.size[0]
    return float(np.median(z)) / fx if len(z) else 0.0


def stands_on(lo: np.ndarray, hi: np.ndarray, el: Element) -> bool:
    """Rule "a thing on the top, not the top's furniture": a box stands on a top when its bottom
    lies within 2 SURFACE_SLAB_M of the top's level, its top above it by RISE_MIN_M, and its
    footprint is under TOP_SHARE of the top's (a table's box, cut at the top where the floor was
    never seen, holds the whole top: what lies on the table is not the table)."""
    area = float(np.prod(np.maximum(hi[:2] - lo[:2], 0.0)))
    top = float(np.prod(el.hi[:2] - el.lo[:2]))
    return (hi[2] >= el.height + RISE_MIN_M and lo[2] >= el.height - 2 * SURFACE_SLAB_M
            and area < TOP_SHARE * top)


def things_on_top(el: Element, cloud: RoomCloud, lab_of: Callable[[int], Optional[np.ndarray]],
                  taken: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[Segment]:
    """The flat things lying on one top: each view that sees it well (`top_views`) gives its
    verdict (`lying_pixels`) on its small grid (`view_grid`), the verdicts are fused on the
    top's cells (`fused_cells`) and cut into regions (`flat_regions`). Only `taken` boxes
    standing on this top count (`stands_on`). `lab_of(k)`: view k's colour on its small grid
    in CIELAB (`small_lab`), or None."""
    idx = top_points(el, cloud)
    plane, near = fused_plane(el, cloud.points[idx])
    grown = grown_footprint(el)
    verdicts = []
    for k in top_views(cloud.frame[idx[near]], len(cloud.views)):
        if not np.any(cloud.views[k].depth > 0):
            continue                  # a view without depth shows no top
        g = view_grid(k, cloud)
        over = over_top(el, g.points, grown)
        v = lying_pixels(plane, g, over, lab_of(k))
        if v is not None:
            verdicts.append((k, g.points, v, pixel_footprint(cloud.views[k], g.z[over & (g.z > 0)])))
    if len(verdicts) < MIN_LYING_VIEWS:
        return []
    on_top = [(lo, hi) for lo, hi in taken if stands_on(lo, hi, el)]
    return flat_regions(plane, fused_cells(el, verdicts), on_top)


def flat_things(tops: Sequence[Element], cloud: RoomCloud, colour_image: Callable[[int], Optional[np.ndarray]],
                taken: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[Segment]:
    """The flat things lying on every top (`things_on_top`), from the views' own depth and colour."""
    labs: dict[int, Optional[np.ndarray]] = {}        # each view's colour is read once for all tops

    def lab_of(k: int) -> Optional[np.ndarray]:
        if k not in labs:
            labs[k] = small_lab(colour_image(cloud.views[k].index), cloud.views[k].depth.shape)
        return labs[k]

    return [seg for el in tops if el.footprint is not None for seg in things_on_top(el, cloud, lab_of, taken)]
