"""Spatial and comparative relations between objects, from 3-D geometry in the gravity frame.

The paper extracts relations with a trained network (F-Net, Sec. III); none is available
offline, so relations are read off gravity-aligned 3-D boxes instead. Every object is an
axis-aligned box in the frame (e1, e2, up) of `horizontal_basis(up)`: width along e1, depth
along e2, height along up. All distances are metres. Notation: bottom(A), top(A) along up;
F(A) the horizontal footprint (a rectangle), |F(A)| its area; F(A)∩F(B) their overlap.

Every stored relation holds whatever the viewpoint (`sg3d.core.relation_rules` says how each is
stored and which exclude each other). Per pair, at most one placement fact, tested in this order:

- IN (containment): A is smaller than B and ≥ IN_MIN_INSIDE_FRACTION of A's box lies inside
  B's box, and B can hold things: B is a container class (CONTAINER_LABELS), or A is a fixture
  set into B (FITTED_LABELS: a sink in a counter), i.e. A's top is flush with B's top (within
  ON_TOLERANCE) and A's bottom lies below it.
- ON (support): A's bottom rests on B's top surface: bottom(A) - top(B) within
  [-max(ON_TOLERANCE, ON_PENETRATION_FRACTION·height(B)), ON_TOLERANCE], A reaches B's top
  (top(A) ≥ top(B) - ON_TOLERANCE) but not below B's bottom, and ≥ ON_MIN_FOOTPRINT_OVERLAP of F(A)
  lies over F(B). An object on a pile is ON the item it touches and ON the furniture the pile
  stands on (much larger footprint, PILE_BASE_FOOTPRINT_RATIO), not ON the pile's middle items.
- ABOVE / BELOW: A is over B with air between, bottom(A) - top(B) in (ON_TOLERANCE,
  ABOVE_MAX_GAP], the smaller footprint mostly over the other (≥ VERTICAL_MIN_FOOTPRINT_OVERLAP)
  and A the smaller of the two (a TV on the wall above a shelf). Stored with B BELOW A.
- UNDER: A is beneath B and covered by it: |F(A)| < |F(B)|, ≥ VERTICAL_MIN_FOOTPRINT_OVERLAP of
  F(A) under F(B), top(A) ≤ top(B) + UNDER_TOP_TOLERANCE, and either A hangs or stands below B
  (top(A) ≤ bottom(B) + ON_TOLERANCE with its centre below B's box, within ABOVE_MAX_GAP: a PC
  tower under a wall shelf) or A
  is tucked under B's top while standing on the same floor (bottoms within BASE_TOLERANCE: a
  stool pushed under a table). A chair at a table whose back rises above the table top is not
  under it: it is NEXT_TO it (what people say: "the chair at the table").
- A small thing at the top level of a support surface (>= SUPPORT_MIN_SIDE wide) and touching
  its edge, but not ON it, gets no placement fact in that frame: the surface may be seen in part.
- NEXT_TO (side by side, not stacked): no fact above holds, both stand on the same level
  (bottoms within BASE_TOLERANCE, or both ON the same object, or both furniture that stands on
  the floor by its kind, FLOOR_STANDING_LABELS: "the chair at the table"), footprints overlap by at most
  NEXT_TO_MAX_FOOTPRINT_OVERLAP of the smaller one (a chair tucked in overlaps a table), and the
  horizontal gap is at most NEXT_TO_GAP_FRACTION of the pair's mean footprint side, kept within
  [NEXT_TO_MIN_GAP, NEXT_TO_MAX_GAP] (two chairs 40 cm apart are next to each other, two cups
  40 cm apart are not). Symmetric: one edge, subject = the smaller id.
- NEAR: no fact above holds and the 3-D surface gap is at most NEAR_SIZE_FRACTION of the larger
  object's largest extent, kept within [NEAR_MIN_GAP, NEAR_MAX_GAP] (a table is near a wider
  ring of things than a cup). Symmetric, stored like NEXT_TO.
- BIGGER_THAN / SMALLER_THAN: box volumes differ by BIGGER_VOLUME_RATIO, only for pairs that
  share a placement fact or a label (else every pair of a room would get one). Stored both ways.

IN_FRONT_OF / BEHIND / LEFT_OF / RIGHT_OF depend on where the camera stood and are never
emitted here; `camera_pose` is accepted and ignored so older callers keep working.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any, Optional, Sequence

import numpy as np

from sg3d.core.geometry import FLOOR_STANDING_LABELS, fixed_precision, horizontal_frame
from sg3d.core.model import UNNAMED_LABEL, ObjectObservation, RelationObservation, vec3
from sg3d.core.relation_rules import edges_of, statement_of

# -- support and stacking ----------------------------------------------------------------
# Depth noise of consumer RGB-D at 1-3 m is ~1-3 cm and object boxes come from partial views,
# so "touching" is allowed a gap or interpenetration of this much.
ON_TOLERANCE = 0.08
# A support's box (from the points of its 2-D box) is often inflated upwards by what stands
# behind it, so the supported object may sink into it by this fraction of its height.
ON_PENETRATION_FRACTION = 0.2
# Most of the supported object's footprint must lie over its support: a cup hanging mostly
# over the table's edge is not "on" it.
ON_MIN_FOOTPRINT_OVERLAP = 0.5
# An object on a pile is ON the furniture under the pile only when that furniture's footprint
# is this many times the pile item's it touches (a table under a stack of magazines).
PILE_BASE_FOOTPRINT_RATIO = 4.0
# ABOVE/BELOW and UNDER: stacked with air in between, within a room's height, the smaller
# footprint mostly over/under the other.
ABOVE_MAX_GAP = 2.0
VERTICAL_MIN_FOOTPRINT_OVERLAP = 0.5
# UNDER: the lower object may rise this far above the covering object's top (noise), no more.
UNDER_TOP_TOLERANCE = 0.08
# Same level: bottoms within a few cm (both on the floor, both on the table).
BASE_TOLERANCE = 0.15
# -- containment -------------------------------------------------------------------------
# IN: most of the object's volume lies inside a container's box.
IN_MIN_INSIDE_FRACTION = 0.6
CONTAINER_LABELS = frozenset({
    "bowl", "cup", "wine glass", "vase", "sink", "refrigerator", "microwave", "oven",
    "toaster", "toilet", "suitcase", "backpack", "handbag", "bed", "couch",
})
# Fixtures set into the furniture that holds them (their rim flush with its top surface).
FITTED_LABELS = frozenset({"sink", "oven"})
# -- side by side ------------------------------------------------------------------------
# A chair tucked in at a table overlaps its footprint; more than this is not "beside".
NEXT_TO_MAX_FOOTPRINT_OVERLAP = 0.9
# A support surface at least this wide (a table, a counter) is often seen only in part: a small
# thing whose bottom is at its top level and that touches its visible part (gap <= NEXT_TO_MIN_GAP)
# may be on the unseen rest, so that frame states nothing about the pair (other views decide).
SUPPORT_MIN_SIDE = 0.5
# Allowed horizontal gap scales with the objects: one mean footprint side, kept within bounds.
NEXT_TO_GAP_FRACTION = 1.0
NEXT_TO_MIN_GAP = 0.10
NEXT_TO_MAX_GAP = 0.60
# NEAR: surface-to-surface distance, half the larger object's largest extent, within bounds.
NEAR_SIZE_FRACTION = 0.5
NEAR_MIN_GAP = 0.40
NEAR_MAX_GAP = 1.00
# -- comparison --------------------------------------------------------------------------
# Box volumes from partial views err by tens of percent; 1.5x is a difference people see.
BIGGER_VOLUME_RATIO = 1.5
# Boxes thinner than this (a sheet of paper, a flat screen seen edge-on) are padded so
# volumes and areas stay meaningful.
MIN_EXTENT = 0.02

VERTICAL_PREDICATES = ("IN", "ON", "UNDER", "ABOVE", "BELOW")


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
        return cls(obs.local_id, obs.label, vec3(obs.mean), vec3(obs.size))

    @classmethod
    def from_points(cls, local_id: str, label: str, points: np.ndarray, up: Sequence[float],
                    lo_percentile: float = 2.0, hi_percentile: float = 98.0) -> "ObjectGeometry":
        """Box of a world point cloud in the gravity frame; percentiles drop depth outliers
        (flying pixels at object borders)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        if len(pts) == 0:
            raise ValueError("no points")
        R = horizontal_frame(up)            # rows e1, e2, up
        local = pts @ R.T
        lo = np.percentile(local, lo_percentile, axis=0)
        hi = np.percentile(local, hi_percentile, axis=0)
        center = R.T @ ((lo + hi) / 2)
        return cls(local_id, label, vec3(center), vec3(hi - lo))


class _Box:
    """An object in gravity-frame coordinates (x along e1, y along e2, z along up)."""

    def __init__(self, geom: ObjectGeometry, R: np.ndarray):
        self.id = geom.local_id
        self.label = geom.label
        # to a fixed precision: boxes found from depth are whole voxels, so their gaps land exactly
        # on limits such as BASE_TOLERANCE, and which side they fall must not be the CPU's choice
        self.c = fixed_precision(R @ np.asarray(geom.center, dtype=np.float64))
        self.s = fixed_precision(np.maximum(np.asarray(geom.size, dtype=np.float64), MIN_EXTENT))
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


def floor_under_room(floor: ObjectGeometry, others: Sequence[ObjectGeometry],
                     up: Sequence[float]) -> ObjectGeometry:
    """Rule "the floor is under the whole room": the floor is seen only where nothing stands on
    it, so for support its footprint is the union of its own and every other object's (its level
    and thickness stay its own)."""
    R = horizontal_frame(up)
    boxes = [_Box(g, R) for g in (floor, *others)]
    lo = np.min([b.lo for b in boxes], axis=0)
    hi = np.max([b.hi for b in boxes], axis=0)
    base = boxes[0]
    lo[2], hi[2] = base.lo[2], base.hi[2]
    return ObjectGeometry(floor.local_id, floor.label, vec3(R.T @ ((lo + hi) / 2)), vec3(hi - lo))


def _overlap_1d(lo_a: Any, hi_a: Any, lo_b: Any, hi_b: Any) -> float:
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

def in_score(a: _Box, b: _Box) -> float:
    """IN: A contained in B (module docstring). Score: the inside fraction."""
    if a.volume >= b.volume:
        return 0.0
    inside = _inside_fraction(a, b)
    if inside < IN_MIN_INSIDE_FRACTION:
        return 0.0
    if b.label in CONTAINER_LABELS:
        return inside
    fitted = (a.label in FITTED_LABELS and abs(a.top - b.top) <= ON_TOLERANCE
              and a.bottom < b.top - ON_TOLERANCE)
    return inside if fitted else 0.0


def on_score(a: _Box, b: _Box) -> float:
    """ON: A's bottom rests on B's top surface (module docstring). Score: footprint share over
    B, lowered by the contact gap."""
    gap = a.bottom - b.top
    penetration = max(ON_TOLERANCE, ON_PENETRATION_FRACTION * b.s[2])
    if not (-penetration <= gap <= ON_TOLERANCE):
        return 0.0
    # A reaches B's top and does not reach below B's bottom: of two thin stacked boxes only the
    # upper one is on the other, and a flat book measured a few cm into a table-top slab is on it.
    # A broad support's slab is often no thicker than what lies on it (the top surface is all the
    # camera sees, raised by the things standing there): a much smaller flat thing filling its
    # height is on it too.
    if a.top < b.top - ON_TOLERANCE:
        return 0.0
    if a.bottom <= b.bottom and b.footprint < PILE_BASE_FOOTPRINT_RATIO * a.footprint:
        return 0.0
    overlap = _footprint_intersection(a, b) / a.footprint
    if overlap < ON_MIN_FOOTPRINT_OVERLAP:
        return 0.0
    allowed = ON_TOLERANCE if gap >= 0 else penetration
    return min(1.0, overlap) * (1.0 - 0.5 * abs(gap) / allowed)


def above_score(a: _Box, b: _Box) -> float:
    """ABOVE: A over B with air between, A the smaller footprint (module docstring)."""
    gap = a.bottom - b.top
    if not (ON_TOLERANCE < gap <= ABOVE_MAX_GAP) or a.footprint > b.footprint:
        return 0.0
    overlap = _footprint_intersection(a, b) / a.footprint
    return min(1.0, overlap) if overlap >= VERTICAL_MIN_FOOTPRINT_OVERLAP else 0.0


def under_score(a: _Box, b: _Box) -> float:
    """UNDER: A beneath B and covered by it (module docstring): below B's box, or tucked under
    B's top while standing on B's floor."""
    if a.footprint >= b.footprint or a.top > b.top + UNDER_TOP_TOLERANCE or a.c[2] >= b.c[2]:
        return 0.0
    overlap = _footprint_intersection(a, b) / a.footprint
    if overlap < VERTICAL_MIN_FOOTPRINT_OVERLAP:
        return 0.0
    # below B's box (its centre too: a flat thing inside a thin table-top slab is not under it)
    hangs_below = a.top <= b.bottom + ON_TOLERANCE and a.c[2] < b.bottom and b.bottom - a.top <= ABOVE_MAX_GAP
    # tucked: the same floor, so a cup inside a table box inflated by the background is not under it
    tucked = abs(a.bottom - b.bottom) <= BASE_TOLERANCE and a.c[2] < b.top - ON_TOLERANCE
    return min(1.0, overlap) if hangs_below or tucked else 0.0


def placement(a: _Box, b: _Box) -> Optional[tuple[_Box, str, _Box, float]]:
    """The one vertical fact of a pair, most specific first, as (subject, type, object, score).
    When a test holds both ways (two nearly identical boxes), the higher box is the subject."""
    for test, name in ((in_score, "IN"), (on_score, "ON"), (under_score, "UNDER"), (above_score, "ABOVE")):
        found = [(s, o, test(s, o)) for s, o in ((a, b), (b, a))]
        found = [f for f in found if f[2] > 0]
        if found:
            s, o, score = max(found, key=lambda f: f[0].c[2] if name in ("ON", "ABOVE") else -f[0].c[2])
            return s, name, o, score
    return None


def at_support_edge(a: _Box, b: _Box) -> bool:
    """The smaller of the two sits at the larger one's top level, touching the edge of a support
    surface (>= SUPPORT_MIN_SIDE wide) seen perhaps only in part: on it or beside it is unknown."""
    small, big = (a, b) if a.footprint < b.footprint else (b, a)
    return (max(big.s[0], big.s[1]) >= SUPPORT_MIN_SIDE and abs(small.bottom - big.top) <= ON_TOLERANCE
            and _horizontal_gap(small, big) <= NEXT_TO_MIN_GAP)


def next_to_score(a: _Box, b: _Box, same_support: bool = False) -> float:
    """NEXT_TO: side by side on one level, within a size-scaled gap (module docstring)."""
    on_floor = a.label in FLOOR_STANDING_LABELS and b.label in FLOOR_STANDING_LABELS
    if abs(a.bottom - b.bottom) > BASE_TOLERANCE and not same_support and not on_floor:
        return 0.0
    if _footprint_intersection(a, b) / min(a.footprint, b.footprint) > NEXT_TO_MAX_FOOTPRINT_OVERLAP:
        return 0.0
    mean_side = (a.s[0] + a.s[1] + b.s[0] + b.s[1]) / 4
    allowed = float(np.clip(NEXT_TO_GAP_FRACTION * mean_side, NEXT_TO_MIN_GAP, NEXT_TO_MAX_GAP))
    gap = _horizontal_gap(a, b)
    return 1.0 - 0.5 * gap / allowed if gap <= allowed else 0.0


def near_score(a: _Box, b: _Box) -> float:
    """NEAR: 3-D surface gap within a distance that grows with the larger object."""
    allowed = float(np.clip(NEAR_SIZE_FRACTION * max(a.s.max(), b.s.max()), NEAR_MIN_GAP, NEAR_MAX_GAP))
    gap = _gap_3d(a, b)
    return 1.0 - 0.5 * gap / allowed if gap <= allowed else 0.0


def comparison(a: _Box, b: _Box) -> Optional[tuple[_Box, _Box, float]]:
    """BIGGER_THAN: (bigger, smaller, score) when the volumes differ by BIGGER_VOLUME_RATIO."""
    if a.volume >= b.volume * BIGGER_VOLUME_RATIO:
        return a, b, 1.0 - b.volume / a.volume
    if b.volume >= a.volume * BIGGER_VOLUME_RATIO:
        return b, a, 1.0 - a.volume / b.volume
    return None


def _drop_pile_middles(on: dict[tuple[str, str], float], boxes: dict[str, _Box]) -> None:
    """A ON B is dropped when A is ON some C that is itself ON B and B is not much larger than
    C (B is the pile's middle, not the furniture under the pile)."""
    for (a, b) in list(on):
        for (a2, c) in list(on):
            if a2 == a and c != b and (c, b) in on \
                    and boxes[b].footprint < PILE_BASE_FOOTPRINT_RATIO * boxes[c].footprint:
                on.pop((a, b), None)
                break


def spatial_relations(objects: Sequence[ObjectGeometry], up: Sequence[float],
                      camera_pose: Optional[np.ndarray] = None) -> list[RelationObservation]:
    """All viewpoint-invariant relations between the objects of one frame or local graph, in
    their stored form (`sg3d.core.relation_rules`): at most one placement fact per pair, NEXT_TO /
    NEAR once with the smaller id as subject, ABOVE with BELOW and BIGGER_THAN with
    SMALLER_THAN as pairs.

    `up`: the room's up direction in world coordinates. `camera_pose` is deprecated and ignored:
    relations that depend on the viewpoint are never stored.
    """
    del camera_pose
    R = horizontal_frame(up)
    boxes = [_Box(o, R) for o in objects]
    by_id = {b.id: b for b in boxes}
    facts: dict[tuple[str, str], tuple[str, str, str, float]] = {}   # unordered pair -> fact
    for a, b in combinations(boxes, 2):
        found = placement(a, b)
        if found is not None:
            s, name, o, score = found
            facts[(a.id, b.id)] = (s.id, name, o.id, score)
    stacked = set(facts)            # a pile's middle loses its ON below, never becomes "beside"
    on = {(s, o): sc for (s, p, o, sc) in facts.values() if p == "ON"}
    _drop_pile_middles(on, by_id)
    facts = {k: f for k, f in facts.items() if f[1] != "ON" or (f[0], f[2]) in on}
    supports: dict[str, set[str]] = {}
    for (low, high) in on:
        supports.setdefault(low, set()).add(high)

    out: list[RelationObservation] = []

    def emit(s: str, predicate: str, o: str, score: float) -> None:
        st = statement_of(s, predicate, o)
        assert st is not None              # only stored predicates are emitted
        out.extend(edges_of(st, float(np.clip(score, 0.0, 1.0))))

    for a, b in combinations(boxes, 2):
        fact = facts.get((a.id, b.id))
        if fact is not None:
            emit(*fact)
        elif (a.id, b.id) not in stacked and not at_support_edge(a, b):
            same_support = bool(supports.get(a.id, set()) & supports.get(b.id, set()))
            score = next_to_score(a, b, same_support)
            if score > 0:
                emit(a.id, "NEXT_TO", b.id, score)
                fact = (a.id, "NEXT_TO", b.id, score)
            else:
                score = near_score(a, b)
                if score > 0:
                    emit(a.id, "NEAR", b.id, score)
                    fact = (a.id, "NEAR", b.id, score)
        if fact is not None or (a.label == b.label and a.label != UNNAMED_LABEL):
            compared = comparison(a, b)
            if compared is not None:
                big, small, score = compared
                emit(big.id, "BIGGER_THAN", small.id, score)
    return out


def side_by_side_on_one_support(relations: Sequence[RelationObservation]) -> list[RelationObservation]:
    """NEXT_TO across the whole sequence: two objects are side by side only when they stand on
    the same support. After voting, a NEXT_TO whose two ends are ON different things (a cup ON
    the table, a chair on the floor: supports {table} vs {}) is dropped. A single frame cannot
    decide this: it often sees only the top of a chair behind a table, as if it stood at the
    table's height; the voted ON edges of the whole sequence say where each object stands."""
    supports: dict[str, set[str]] = {}
    for r in relations:
        if r.predicate == "ON":
            supports.setdefault(r.subject, set()).add(r.object)
    return [r for r in relations if r.predicate != "NEXT_TO"
            or supports.get(r.subject, set()) == supports.get(r.object, set())]
