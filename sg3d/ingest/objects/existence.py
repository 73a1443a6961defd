"""Does a hypothesis exist? Multi-view evidence, negative evidence included.

A real object is detected in a fair share of the frames that show it; a misreading (a "tv" on a
stack of magazines, a "cell phone" on a box) is detected once or twice among the many frames
that show the same place. So for each hypothesis we count the detected frames in which it
*should* have been seen (`expected_in_view`: it projects inside the image, large enough for the
detector, and the depth there does not show something in front of it) and those in which it was
detected, and weigh the two explanations (`existence_probability`).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import cv2
import numpy as np

from sg3d.ingest.objects.attributes import BOX_HIGH_PERCENTILE, BOX_LOW_PERCENTILE

# A frame's depth is kept at 1/DEPTH_FACTOR resolution for the visibility test and the room's
# cloud (objects are tens of pixels wide at 640x480; 160x120 is plenty and costs 77 KB a frame),
# but never on a grid narrower than MIN_GRID_WIDTH: a 320x240 camera's depth is halved, not
# quartered, so a desk top seen from across a room keeps the pixels a 640x480 camera gives it.
DEPTH_FACTOR = 4
MIN_GRID_WIDTH = 160


def depth_factor(width: int) -> int:
    """Rule "a grid fine enough": shrink a `width`-pixel depth image by DEPTH_FACTOR, or by the
    largest whole factor that keeps it at least MIN_GRID_WIDTH pixels wide (1 for an image no
    wider)."""
    return max(1, min(DEPTH_FACTOR, width // MIN_GRID_WIDTH))


# Visible: the centre projects this far inside the image border (fraction of width/height) ...
BORDER_MARGIN = 0.05
# ... at least this many pixels across (SSD300 sees little below ~20 px at 640x480) ...
MIN_PIXELS = 24.0
# ... no farther than the detector resolves household objects ...
MAX_RANGE_M = 4.5
# A view counts fully once the object spans this many pixels; smaller views count in proportion
# (the detector's hit rate falls with apparent size: 640x480 is shrunk to 300x300).
FULL_VIEW_PIXELS = 120.0
# Tiles enlarge a frame to find what is small or far. An object as big in the image as the full
# frame sees fully (median box side >= FULL_VIEW_PIXELS) that only tiles ever named is a tile
# artefact: a zoomed-in texture (a cabinet front read as a laptop) recurs in every view of it.
TILE_ONLY_MAX_PIXELS = FULL_VIEW_PIXELS
# ... and nothing stands in front: the surface seen there is not nearer than the object's own
# front (half its extent before its centre) by more than this.
OCCLUSION_TOLERANCE_M = 0.15

# The two explanations of k detections in n views: a real object is detected in a view with
# probability P_DETECT_REAL, a misreading recurs with P_DETECT_FALSE; prior odds of a real object.
P_DETECT_REAL = 0.25
P_DETECT_FALSE = 0.10
PRIOR_REAL = 0.5
# Kept when the probability passes EXISTENCE_THRESHOLD and it was detected at least MIN_DETECTIONS
# times (the authors' code: twice).
EXISTENCE_THRESHOLD = 0.5
MIN_DETECTIONS = 2


# An object is never too small for its label when the image border cuts at least this share of
# its views (the median view is a cut one).
CUT_SHARE = 0.5

# A label the size prior leaves standing replaces the best one only with at least this share of
# its evidence (fused score).
RELABEL_MIN_SHARE = 0.5

# The share of an object's extent its measured box spans: percentiles of points spread evenly
# along an axis leave out the two tails.
MEASURED_SHARE = (BOX_HIGH_PERCENTILE - BOX_LOW_PERCENTILE) / 100.0

CLASS_SIZES_FILE = Path(__file__).resolve().parents[1] / "data" / "class_sizes.json"


@lru_cache(maxsize=1)
def class_sizes() -> dict[str, tuple[float, float]]:
    data = json.loads(CLASS_SIZES_FILE.read_text(encoding="utf-8"))
    return {k: (float(v[0]), float(v[1])) for k, v in data["sizes"].items()}


@lru_cache(maxsize=1)
def class_typical() -> dict[str, dict]:
    """Per class, a typical object as it lies in a room (`data/class_sizes.json`, "typical"):
    {size: box sides sorted largest first, shapes: shape classes its box may take (None: none
    fits), support: surface | work | floor | any}. Classes not listed have none."""
    data = json.loads(CLASS_SIZES_FILE.read_text(encoding="utf-8"))
    return {k: {"size": tuple(float(x) for x in v["size"]), "shapes": tuple(v["shapes"]), "support": v["support"]}
            for k, v in data.get("typical", {}).items()}


_SAME = object()
Size = Union[Sequence[float], np.ndarray]


def size_plausible(label: str, size: Size, small_size: object = _SAME) -> bool:
    """Size prior: the object's largest extent could be one in its class's plausible range
    (`data/class_sizes.json`, world knowledge, true sizes); classes without a range always pass.
    The measured box spans MEASURED_SHARE of the object (percentiles of its points), so the
    smallest plausible object measures MEASURED_SHARE * min: min * MEASURED_SHARE <= extent <= max
    (trimming tails never makes a box bigger than its object). Too big is judged on `size`; too
    small on `small_size` (`size` itself unless given; `judged_sizes`), never when it is None."""
    bounds = class_sizes().get(label)
    if bounds is None:
        return True
    small = size if small_size is _SAME else small_size
    too_small = small is not None and float(np.max(np.asarray(small, dtype=np.float64))) < bounds[0] * MEASURED_SHARE
    return float(max(size)) <= bounds[1] and not too_small


def plausible_labels(labels: Sequence[str], scores: Sequence[float], size: Size,
                     small_size: object = _SAME) -> tuple[list[str], list[float]]:
    """The top-k labels without those the size prior rules out (`size_plausible`, with
    `small_size`), order kept: a 45 cm box called
    "cell phone" (0.4) first and "book" (0.2) second becomes a book. Empty when no label fits,
    or when the best label that fits has less than RELABEL_MIN_SHARE of the best label's
    evidence: a faint third guess (a plastic box: "cell phone" 0.28, "remote" 0.10, "book" 0.09)
    is not a reading of the object, only what is left."""
    kept = [(lbl, s) for lbl, s in zip(labels, scores) if size_plausible(lbl, size, small_size)]
    if kept and scores and kept[0][1] < RELABEL_MIN_SHARE * float(scores[0]):
        kept = []
    return [lbl for lbl, _ in kept], [s for _, s in kept]


def judged_sizes(sightings: Sequence, box_size: Size) -> tuple[np.ndarray, Optional[np.ndarray]]:
    """Rules "the median view" and "a cut view is a part": the sizes the size prior
    (`size_plausible`) judges an object by. Too big: per axis the median of its views' boxes
    (`Sighting.attrs.size`), not the union `box_size` of its views (a view whose box ran along the
    floor or took in a neighbour is outvoted). Too small: `box_size` (a part seen in one view and
    the rest in another add up), and never when the image border cuts at least CUT_SHARE of its
    views (`attrs.cut`): what those show is a part of something that goes on beyond the image."""
    sizes = np.array([s.attrs.size for s in sightings], dtype=np.float64)
    cut = np.array([bool(getattr(s.attrs, "cut", False)) for s in sightings], dtype=bool)
    small = None if cut.mean() >= CUT_SHARE else np.asarray(box_size, dtype=np.float64)
    return np.median(sizes, axis=0), small


def tile_artefact(detections: Sequence) -> bool:
    """True when no detection of an object was named by the full frame (`Detection.full_frame`)
    although its median box side max(x2 - x1, y2 - y1) is at least TILE_ONLY_MAX_PIXELS."""
    if not detections or any(d.full_frame for d in detections):
        return False
    sides = [max(d.box[2] - d.box[0], d.box[3] - d.box[1]) for d in detections]
    return float(np.median(sides)) >= TILE_ONLY_MAX_PIXELS


@dataclass(frozen=True)
class View:
    """What the visibility test needs of a detected frame: its index, camera, and small depth."""

    index: int
    K: np.ndarray
    pose: np.ndarray               # camera-to-world
    size: tuple[int, int]          # full-resolution (width, height)
    depth: np.ndarray              # metres on the small grid (`depth_factor`), 0 = unknown

    @property
    def factor(self) -> float:
        """Full-resolution pixels per small-grid pixel."""
        return self.size[0] / self.depth.shape[1]

    @classmethod
    def of(cls, frame: Any) -> "View":
        w, h = frame.size
        f = depth_factor(w)
        small = cv2.resize(frame.depth, (max(1, w // f), max(1, h // f)),
                           interpolation=cv2.INTER_NEAREST)
        return cls(frame.index, frame.K, frame.pose, (w, h), small)


def expected_in_view(centre: Any, extent: float, view: View) -> Optional[float]:
    """How much should an object with box centre `centre` (world) and largest extent `extent` (m)
    have been seen in `view`? A weight in (0, 1] when it projects inside the image
    (BORDER_MARGIN), at least MIN_PIXELS across, within MAX_RANGE_M, and the depth around its
    projection is not nearer than its front (z - extent/2) by more than OCCLUSION_TOLERANCE_M:
    min(1, pixels / FULL_VIEW_PIXELS). 0.0: outside, too small or occluded. None: no depth there."""
    world_to_cam = np.linalg.inv(view.pose)
    p = world_to_cam[:3, :3] @ np.asarray(centre, dtype=np.float64) + world_to_cam[:3, 3]
    z = float(p[2])
    if z <= 0.1 or z > MAX_RANGE_M:
        return 0.0
    K = view.K
    u = K[0, 0] * p[0] / z + K[0, 2]
    v = K[1, 1] * p[1] / z + K[1, 2]
    w, h = view.size
    if not (BORDER_MARGIN * w <= u < (1 - BORDER_MARGIN) * w and BORDER_MARGIN * h <= v < (1 - BORDER_MARGIN) * h):
        return 0.0
    pixels = K[0, 0] * extent / z
    if pixels < MIN_PIXELS:
        return 0.0
    du, dv = int(u / view.factor), int(v / view.factor)
    patch = view.depth[max(0, dv - 1):dv + 2, max(0, du - 1):du + 2]
    seen = patch[patch > 0]
    if seen.size == 0:
        return None
    if float(np.median(seen)) < z - extent / 2 - OCCLUSION_TOLERANCE_M:
        return 0.0
    return min(1.0, pixels / FULL_VIEW_PIXELS)


def existence_probability(detected: int, expected: float, p_real: float = P_DETECT_REAL,
                          p_false: float = P_DETECT_FALSE, prior: float = PRIOR_REAL) -> float:
    """P(real | k of n) by Bayes over two binomial explanations of k detections in n views:

        L_real  = p_r^k (1 - p_r)^(n - k),   L_false = p_f^k (1 - p_f)^(n - k)
        P = prior L_real / (prior L_real + (1 - prior) L_false)

    with k = detections, n = max(expected views, k) (a detection is a view that showed it; n may
    be fractional: views weighted by apparent size)."""
    k = int(detected)
    n = max(float(expected), k)
    log_real = k * math.log(p_real) + (n - k) * math.log1p(-p_real)
    log_false = k * math.log(p_false) + (n - k) * math.log1p(-p_false)
    log_odds = math.log(prior) - math.log1p(-prior) + log_real - log_false
    if log_odds > 50:
        return 1.0
    return 1.0 / (1.0 + math.exp(-log_odds))


@dataclass(frozen=True)
class Evidence:
    detected: int          # detected frames that hold a sighting of it
    expected: float        # detected frames that should have shown it, weighted by apparent size
    probability: float

    @property
    def ratio(self) -> float:
        return self.detected / self.expected if self.expected else 0.0


def evidence(centre: Any, extent: float, detected_frames: set[int], views: list[View], **params: Any) -> Evidence:
    """Count views that should have shown the object (weighted by apparent size) and the ones that
    did; a detection counts as a full view even where the visibility test cannot tell."""
    expected = 0.0
    for view in views:
        expected += 1.0 if view.index in detected_frames else (expected_in_view(centre, extent, view) or 0.0)
    k = len(detected_frames)
    return Evidence(k, expected, existence_probability(k, expected, **params))


def exists(ev: Evidence, threshold: float = EXISTENCE_THRESHOLD, min_detections: int = MIN_DETECTIONS) -> bool:
    """The existence decision: probability >= threshold and at least min_detections detections."""
    return ev.detected >= min_detections and ev.probability >= threshold
