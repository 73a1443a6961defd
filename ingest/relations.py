"""Spatial and comparative relations between objects, from 3-D geometry.

The paper extracts relations with a trained network (F-Net, Sec. III); none is available
offline, so relations are read off gravity-aligned 3-D boxes instead. Every object is an
axis-aligned box in the frame (e1, e2, up) of `horizontal_basis(up)`: width along e1, depth
along e2, height along up. All distances are metres.

Chosen to keep the graph sparse (the paper's point): a pair gets at most one "vertical" fact
(IN, ON, UNDER, ABOVE/BELOW), NEXT_TO only between things on the same support level, NEAR only
for close pairs with no more specific relation, IN_FRONT_OF/BEHIND only with a camera and
lateral overlap, and BIGGER_THAN/SMALLER_THAN only for pairs that already share a spatial
relation or carry the same label. Relations cost O(n^2) box tests but emit O(n) edges for
typical rooms.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Optional, Sequence

import numpy as np

from ingest.model import ObjectObservation, RelationObservation

# -- support (ON / UNDER) ----------------------------------------------------------------
# Depth noise of consumer RGB-D at 1-3 m is ~1-3 cm and object boxes come from partial views,
# so "touching" is allowed a gap or interpenetration of this much.
ON_TOLERANCE = 0.08
# A support's box (from the points of its 2-D box) is often inflated upwards by what stands
# behind it, so the supported object may sink into it by this fraction of its height.
ON_PENETRATION_FRACTION = 0.2
# Most of the supported object's footprint must lie over its support: a cup hanging mostly
# over the table's edge is not "on" it.
ON_MIN_FOOTPRINT_OVERLAP = 0.5
# UNDER: the lower object stands on the same floor and is mostly covered by the upper one's
# footprint; a chair tucked under a table may rise this far above the table top with its back.
UNDER_MIN_FOOTPRINT_OVERLAP = 0.5
UNDER_TOP_TOLERANCE = 0.20
# ABOVE/BELOW: stacked with air in between, within a room's height, footprints overlapping.
ABOVE_MAX_GAP = 2.0
ABOVE_MIN_FOOTPRINT_OVERLAP = 0.3
# -- containment -------------------------------------------------------------------------
# IN: most of the object's volume lies inside a container's box.
IN_MIN_INSIDE_FRACTION = 0.6
CONTAINER_LABELS = frozenset({
    "bowl", "cup", "wine glass", "vase", "sink", "refrigerator", "microwave", "oven",
    "toaster", "toilet", "suitcase", "backpack", "handbag", "bed", "couch",
})
# -- side by side ------------------------------------------------------------------------
# Same support level: bases within a few cm (e.g. both on the floor, both on the table).
NEXT_TO_BASE_TOLERANCE = 0.15
# Footprints may touch a little (boxes of neighbours often overlap by noise), not more.
NEXT_TO_MAX_FOOTPRINT_OVERLAP = 0.2
# Allowed horizontal gap scales with the objects: one mean footprint side (two chairs 40 cm
# apart are next to each other, two cups 40 cm apart are not), kept within [10, 60] cm.
NEXT_TO_GAP_FRACTION = 1.0
NEXT_TO_MIN_GAP = 0.10
NEXT_TO_MAX_GAP = 0.60
# NEAR: surface-to-surface distance; an arm's reach.
NEAR_MAX_GAP = 0.50
# -- relative to the camera --------------------------------------------------------------
# IN_FRONT_OF: A's far face may reach this far past B's near face (noise); the two must share
# at least this fraction of the narrower lateral extent and stand within this depth gap.
FRONT_TOLERANCE = 0.05
FRONT_MIN_LATERAL_OVERLAP = 0.3
FRONT_MAX_DEPTH_GAP = 1.5
# -- comparison --------------------------------------------------------------------------
# Box volumes from partial views err by tens of percent; 1.5x is a difference people see.
BIGGER_VOLUME_RATIO = 1.5
# Boxes thinner than this (a sheet of paper, a flat screen seen edge-on) are padded so
# volumes and areas stay meaningful.
MIN_EXTENT = 0.02

VERTICAL_PREDICATES = ("IN", "ON", "UNDER", "ABOVE", "BELOW")


def horizontal_basis(up: Sequence[float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A right-handed orthonormal frame (e1, e2, up) with e1, e2 horizontal.

    e1 is the world x axis made horizontal (world y if x is nearly vertical), so the same
    `up` always gives the same frame: sizes computed by other modules in this frame agree.
    """
    u = np.asarray(up, dtype=np.float64)
    u = u / np.linalg.norm(u)
    seed = np.array([1.0, 0.0, 0.0]) if abs(u[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = seed - seed.dot(u) * u
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    return e1, e2, u


@dataclass
class ObjectGeometry:
    """An object's 3-D box: `center` in world coordinates, `size` = (w, d, h) along
    (e1, e2, up) of `horizontal_basis(up)`."""

    local_id: str
    label: str
    center: tuple[float, float, float]
    size: tuple[float, float, float]

    @classmethod
    def from_observation(cls, obs: ObjectObservation) -> "ObjectGeometry":
        return cls(obs.local_id, obs.label, tuple(obs.mean), tuple(obs.size))

    @classmethod
    def from_points(cls, local_id: str, label: str, points: np.ndarray, up: Sequence[float],
                    lo_percentile: float = 2.0, hi_percentile: float = 98.0) -> "ObjectGeometry":
        """Box of a world point cloud in the gravity frame; percentiles drop depth outliers
        (flying pixels at object borders)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        if len(pts) == 0:
            raise ValueError("no points")
        R = np.stack(horizontal_basis(up))            # rows e1, e2, up
        local = pts @ R.T
        lo = np.percentile(local, lo_percentile, axis=0)
        hi = np.percentile(local, hi_percentile, axis=0)
        center = R.T @ ((lo + hi) / 2)
        return cls(local_id, label, tuple(float(v) for v in center), tuple(float(v) for v in hi - lo))


class _Box:
    """An object in gravity-frame coordinates (x along e1, y along e2, z along up)."""

    def __init__(self, geom: ObjectGeometry, R: np.ndarray):
        self.id = geom.local_id
        self.label = geom.label
        self.c = R @ np.asarray(geom.center, dtype=np.float64)
        self.s = np.maximum(np.asarray(geom.size, dtype=np.float64), MIN_EXTENT)
        self.lo = self.c - self.s / 2
        self.hi = self.c + self.s / 2

    @property
    def bottom(self) -> float:
        return float(self.lo[2])

    @property
    def top(self) -> float:
        return float(self.hi[2])

    @property
    def footprint(self) -> float:
        return float(self.s[0] * self.s[1])

    @property
    def volume(self) -> float:
        return float(np.prod(self.s))

    def extent_along(self, v: np.ndarray) -> tuple[float, float]:
        """Interval covered along a horizontal unit direction v (gravity-frame coordinates)."""
        centre = float(self.c[:2] @ v[:2])
        half = float(abs(v[0]) * self.s[0] + abs(v[1]) * self.s[1]) / 2
        return centre - half, centre + half


def _overlap_1d(lo_a, hi_a, lo_b, hi_b) -> float:
    return max(0.0, min(hi_a, hi_b) - max(lo_a, lo_b))


def _footprint_intersection(a: _Box, b: _Box) -> float:
    return _overlap_1d(a.lo[0], a.hi[0], b.lo[0], b.hi[0]) * _overlap_1d(a.lo[1], a.hi[1], b.lo[1], b.hi[1])


def _horizontal_gap(a: _Box, b: _Box) -> float:
    dx = max(0.0, max(a.lo[0], b.lo[0]) - min(a.hi[0], b.hi[0]))
    dy = max(0.0, max(a.lo[1], b.lo[1]) - min(a.hi[1], b.hi[1]))
    return float(np.hypot(dx, dy))


def _gap_3d(a: _Box, b: _Box) -> float:
    d = np.maximum(0.0, np.maximum(a.lo, b.lo) - np.minimum(a.hi, b.hi))
    return float(np.linalg.norm(d))


def _inside_fraction(a: _Box, b: _Box) -> float:
    inter = np.prod([_overlap_1d(a.lo[k], a.hi[k], b.lo[k], b.hi[k]) for k in range(3)])
    return float(inter / a.volume)


# -- per-predicate tests: each returns a score in (0, 1] or 0 when the relation does not hold

def _in_score(a: _Box, b: _Box) -> float:
    if b.label not in CONTAINER_LABELS or b.volume <= a.volume:
        return 0.0
    inside = _inside_fraction(a, b)
    return inside if inside >= IN_MIN_INSIDE_FRACTION else 0.0


def _on_score(a: _Box, b: _Box) -> float:
    gap = a.bottom - b.top
    penetration = max(ON_TOLERANCE, ON_PENETRATION_FRACTION * b.s[2])
    if not (-penetration <= gap <= ON_TOLERANCE) or a.footprint >= b.footprint:
        return 0.0
    if a.top < b.top - ON_TOLERANCE:           # A must reach B's top surface
        return 0.0
    overlap = _footprint_intersection(a, b) / a.footprint
    if overlap < ON_MIN_FOOTPRINT_OVERLAP:
        return 0.0
    allowed = ON_TOLERANCE if gap >= 0 else penetration
    return min(1.0, overlap) * (1.0 - 0.5 * abs(gap) / allowed)


def _under_score(a: _Box, b: _Box) -> float:
    # compared with B's top, not its centre: a table's box reaches the floor, so a chair
    # tucked under it has its centre at the table's mid-height
    if a.c[2] >= b.top - ON_TOLERANCE or a.top > b.top + UNDER_TOP_TOLERANCE or a.footprint >= b.footprint:
        return 0.0
    # tucked under furniture standing on the same floor; without this a cup inside a table
    # box inflated by the background would be "under" the table
    if a.bottom > b.bottom + NEXT_TO_BASE_TOLERANCE:
        return 0.0
    overlap = _footprint_intersection(a, b) / a.footprint
    return min(1.0, overlap) if overlap >= UNDER_MIN_FOOTPRINT_OVERLAP else 0.0


def _above_score(a: _Box, b: _Box) -> float:
    gap = a.bottom - b.top
    if not (ON_TOLERANCE < gap <= ABOVE_MAX_GAP):
        return 0.0
    overlap = _footprint_intersection(a, b) / min(a.footprint, b.footprint)
    return min(1.0, overlap) if overlap >= ABOVE_MIN_FOOTPRINT_OVERLAP else 0.0


def _vertical_relation(a: _Box, b: _Box) -> Optional[tuple[str, float]]:
    """The one vertical fact A -> B, most specific first."""
    for predicate, test in (("IN", _in_score), ("ON", _on_score), ("UNDER", _under_score),
                            ("ABOVE", _above_score)):
        score = test(a, b)
        if score > 0:
            return predicate, score
    score = _above_score(b, a)
    if score > 0:
        return "BELOW", score
    return None


def _next_to_score(a: _Box, b: _Box) -> float:
    if abs(a.bottom - b.bottom) > NEXT_TO_BASE_TOLERANCE:
        return 0.0
    if _footprint_intersection(a, b) / min(a.footprint, b.footprint) > NEXT_TO_MAX_FOOTPRINT_OVERLAP:
        return 0.0
    mean_side = (a.s[0] + a.s[1] + b.s[0] + b.s[1]) / 4
    allowed = float(np.clip(NEXT_TO_GAP_FRACTION * mean_side, NEXT_TO_MIN_GAP, NEXT_TO_MAX_GAP))
    gap = _horizontal_gap(a, b)
    return 1.0 - 0.5 * gap / allowed if gap <= allowed else 0.0


def _near_score(a: _Box, b: _Box) -> float:
    gap = _gap_3d(a, b)
    return 1.0 - 0.5 * gap / NEAR_MAX_GAP if gap <= NEAR_MAX_GAP else 0.0


def _camera_axes(camera_pose: np.ndarray, R: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """Horizontal viewing direction and its lateral axis, in gravity-frame coordinates.
    Camera convention: OpenCV (x right, y down, z forward), pose = camera-to-world."""
    forward = R @ np.asarray(camera_pose, dtype=np.float64)[:3, 2]
    forward[2] = 0.0
    norm = np.linalg.norm(forward)
    if norm < 0.2:          # looking almost straight up or down: no usable "front"
        return None
    forward /= norm
    lateral = np.array([-forward[1], forward[0], 0.0])
    return forward, lateral


def _in_front_score(a: _Box, b: _Box, forward: np.ndarray, lateral: np.ndarray) -> float:
    a_near, a_far = a.extent_along(forward)
    b_near, b_far = b.extent_along(forward)
    if a_far > b_near + FRONT_TOLERANCE or b_near - a_far > FRONT_MAX_DEPTH_GAP:
        return 0.0
    a_lo, a_hi = a.extent_along(lateral)
    b_lo, b_hi = b.extent_along(lateral)
    overlap = _overlap_1d(a_lo, a_hi, b_lo, b_hi) / min(a_hi - a_lo, b_hi - b_lo)
    return min(1.0, overlap) if overlap >= FRONT_MIN_LATERAL_OVERLAP else 0.0


def _comparison(a: _Box, b: _Box) -> Optional[tuple[str, str, float]]:
    """(predicate A->B, inverse, score) when the volumes differ enough."""
    if a.volume >= b.volume * BIGGER_VOLUME_RATIO:
        return "BIGGER_THAN", "SMALLER_THAN", 1.0 - b.volume / a.volume
    if b.volume >= a.volume * BIGGER_VOLUME_RATIO:
        return "SMALLER_THAN", "BIGGER_THAN", 1.0 - a.volume / b.volume
    return None


def spatial_relations(objects: Sequence[ObjectGeometry], up: Sequence[float],
                      camera_pose: Optional[np.ndarray] = None) -> list[RelationObservation]:
    """All relations between the objects of one local graph, for every ordered pair.

    `up`: the room's up direction in world coordinates; `camera_pose`: 4x4 camera-to-world of
    the keyframe, needed only for IN_FRONT_OF / BEHIND.
    """
    R = np.stack(horizontal_basis(up))
    boxes = [_Box(o, R) for o in objects]
    axes = _camera_axes(camera_pose, R) if camera_pose is not None else None
    out: list[RelationObservation] = []

    def emit(s: _Box, predicate: str, o: _Box, score: float) -> None:
        out.append(RelationObservation(s.id, predicate, o.id, float(np.clip(score, 0.0, 1.0))))

    for a, b in combinations(boxes, 2):
        related = False
        for s, o in ((a, b), (b, a)):
            vertical = _vertical_relation(s, o)
            if vertical is not None:
                emit(s, vertical[0], o, vertical[1])
                related = True
        stacked = related
        if not stacked:
            score = _next_to_score(a, b)
            if score > 0:
                emit(a, "NEXT_TO", b, score)
                emit(b, "NEXT_TO", a, score)
                related = True
        if axes is not None and not stacked:
            for s, o in ((a, b), (b, a)):
                score = _in_front_score(s, o, *axes)
                if score > 0:
                    emit(s, "IN_FRONT_OF", o, score)
                    emit(o, "BEHIND", s, score)
                    related = True
                    break
        if not related:
            score = _near_score(a, b)
            if score > 0:
                emit(a, "NEAR", b, score)
                emit(b, "NEAR", a, score)
                related = True
        if related or a.label == b.label:
            comparison = _comparison(a, b)
            if comparison is not None:
                forward_pred, inverse_pred, score = comparison
                emit(a, forward_pred, b, score)
                emit(b, inverse_pred, a, score)
    return out
