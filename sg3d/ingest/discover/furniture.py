"""Furniture named from its shape: what a COCO detector cannot name (desks, cabinets) or misnames
(a sideboard called "dining table"), read off the room's structure in the gravity frame.

Each rule is one function:
- `part_of_furniture`: a level lying over a floor-standing object (a chair's or a couch's seat, a
  table's top) is part of that object, not structure;
- `floor_seen_under`: the share of a horizontal surface's footprint under which the floor was
  seen: furniture with knee space shows the floor below its top, a solid box hides it;
- `desk_shaped`: a top at desk height (DESK_TOP_HEIGHT) with knee space below is a desk;
- `cabinet_shaped`: a top below table height that hides the floor under it is a cabinet, whatever
  a detector called it;
- `couch_shaped`: a seat level (COUCH_SEAT_HEIGHT) with a back or an arm longer than any chair's
  beside it is a couch; its parts are one object (`couch_parts`, `couch_box`);
- `carrel_panel` (`sg3d.core.geometry`, shared with the merge of a later scan): a thin vertical
  panel standing beside a desk's worktop and rising above it is the carrel's side, part of the desk;
- `base_under_seat`: a low piece on the floor under a seat is that seat's base (a chair's
  five-star base), not an object of its own.
A node named by these rules says so (`named_by = "shape"`); where a detector's label is
overruled, its label stays among the node's top-k labels.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Optional, Sequence

import numpy as np

from sg3d.core.geometry import (  # noqa: F401  (the carrel rule is shared with the merge)
    CARREL_PANEL_MAX_THICKNESS_M,
    CARREL_REACH_M,
    DESK_LABEL,
    SOLID_TO_THE_FLOOR,
    boxes_touch,
    carrel_panel,
)
from sg3d.core.model import ObjectObservation, vec3
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import FLOOR_SLAB_M, SURFACE_CELL_M, Element

# Desk and table tops stand 0.60-0.80 m above the floor (office desks 0.72-0.76 m, dining tables
# 0.72-0.78 m; a low coffee table or a sideboard is below, a counter above).
DESK_TOP_HEIGHT = (0.60, 0.80)
# Knee space: the floor was seen under at least this share of the top's footprint cells (a desk
# seen from 1-2 m shows the floor under it: 0.57-0.99 of its top in the study room). A solid box
# to the floor hides what is under it: below CABINET_FLOOR_SHARE (a sideboard: 0.22).
KNEE_FLOOR_SHARE = 0.5
CABINET_FLOOR_SHARE = 0.35
# A desk top has room for a person's work: at least this area (m^2).
DESK_MIN_AREA = 0.15
# A level is part of a floor-standing object when this share of its footprint lies inside the
# object's box and its height lies within the box's (with FURNITURE_MARGIN_M of slack).
PART_SHARE = 0.5
FURNITURE_MARGIN_M = 0.05
# Carrels and office rows: one long worktop is several desks, each between two vertical panels.
# A panel crosses the top: in a SURFACE_CELL_M slice across the top, points fill at least
# PANEL_MIN_FILL of the (across, height) cells both above the top (up to PANEL_REACH_M) and below
# it (down to PANEL_FLOOR_GAP_M over the floor); the slice is the fullest within PANEL_WINDOW_M,
# and each desk left is at least DESK_MIN_WIDTH wide.
PANEL_MIN_FILL = 0.15
PANEL_REACH_M = 0.8
PANEL_FLOOR_GAP_M = 0.1
PANEL_WINDOW_M = 0.2
DESK_MIN_WIDTH = 0.5
# Couch and sofa seats stand 0.35-0.50 m above the floor (seat cushions 0.38-0.48 m; a bed's
# mattress is higher, a coffee table as low but with nothing raised beside it).
COUCH_SEAT_HEIGHT = (0.35, 0.50)
# A back or an arm: a part within COUCH_JOIN_M of the seat level seen (a dark or slanted cushion
# shows only part of its seat as a level; back and arms stand within a cushion's depth of it) that
# rises from the seat (its bottom at or below the seat level) at least COUCH_RISE_M above it, tops
# out by COUCH_MAX_TOP_M (sofa backs and arms stand 0.6-1.0 m; taller is a cabinet or a wall beside
# the level) and runs at least COUCH_MIN_PART_M along its longest horizontal axis: a sofa's back is
# 1.2 m wide and more and its arms 0.75-0.95 m deep, while a chair's back or arm is 0.40-0.55 m
# (the study room's chairs measure 0.58-0.65 m over back and arms together, its couch's arm 0.93 m).
COUCH_JOIN_M = 0.35
COUCH_RISE_M = 0.15
COUCH_MAX_TOP_M = 1.0
COUCH_MIN_PART_M = 0.80
COUCH_LABEL = "couch"
# A seat's base: a piece whose top is at most BASE_MAX_TOP_M above the floor (a five-star chair
# base with its casters stands 0.10-0.15 m; a seat is at 0.35 m or more) and whose footprint
# overlaps the footprint of a seat above it.
BASE_MAX_TOP_M = 0.16
# ... and whose footprint overlaps, or lies within this of, the seat's: a five-star base is 0.60-0.70 m
# across under a 0.45-0.50 m seat, so its legs reach about 0.10 m beyond the seat's edge (and a
# seat's box measured off the floor ends at the seat and back).
BASE_REACH_M = 0.10
# What stands above a base as a seat: its bottom at least this high (a chair's seat, seen without
# its legs) or a named floor-standing object's box.
SEAT_MIN_BOTTOM_M = 0.25
# Detector labels a low, solid top overrules (a sideboard looks like a table from above).
TABLE_LABELS = ("dining table",)
CABINET_LABEL = "cabinet"


def footprint_cells(surface: Element, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(point indices, their footprint cells) of the points whose (a, b) fall on the surface's
    footprint (any height)."""
    assert surface.footprint is not None and surface.origin is not None
    fp = surface.footprint
    cells = np.floor((points[:, :2] - surface.origin) / SURFACE_CELL_M).astype(int)
    inside = (cells >= 0).all(axis=1) & (cells[:, 0] < fp.shape[0]) & (cells[:, 1] < fp.shape[1])
    idx = np.flatnonzero(inside)
    on = fp[cells[idx, 0], cells[idx, 1]]
    return idx[on], cells[idx[on]]


def floor_seen_under(surface: Element, cloud: RoomCloud) -> float:
    """Rule "floor seen under": the share of the surface's footprint cells with a floor point
    (within FLOOR_SLAB_M of the floor) below them."""
    assert surface.footprint is not None
    floor = cloud.points[np.abs(cloud.points[:, 2]) <= FLOOR_SLAB_M]
    _, cells = footprint_cells(surface, floor)
    seen = np.zeros(surface.footprint.shape, bool)
    seen[cells[:, 0], cells[:, 1]] = True
    return float((seen & surface.footprint).sum() / max(1, surface.footprint.sum()))


def floor_seen_in_footprint(lo: np.ndarray, hi: np.ndarray, cloud: RoomCloud) -> float:
    """The share of a gravity box's footprint cells (SURFACE_CELL_M) with a floor point (within
    FLOOR_SLAB_M of the floor) in them."""
    n = np.maximum(np.round((hi[:2] - lo[:2]) / SURFACE_CELL_M).astype(int), 1)
    p = cloud.points[np.abs(cloud.points[:, 2]) <= FLOOR_SLAB_M]
    cells = np.floor((p[:, :2] - lo[:2]) / SURFACE_CELL_M).astype(int)
    cells = cells[(cells >= 0).all(axis=1) & (cells < n).all(axis=1)]
    seen = np.zeros(tuple(n), bool)
    seen[cells[:, 0], cells[:, 1]] = True
    return float(seen.mean())


def open_below(label: str, lo: np.ndarray, hi: np.ndarray, cloud: RoomCloud) -> bool:
    """Rule "not solid to the floor": a detection of a kind that stands solid to the floor
    (SOLID_TO_THE_FLOOR: a refrigerator, an oven) over whose box's footprint the floor was seen in
    at least CABINET_FLOOR_SHARE of the cells (`floor_seen_in_footprint`: it does not hide the
    floor as a solid box does) is no such thing: the detector read something open below (a
    carrel's panel and its desk) as one."""
    return label in SOLID_TO_THE_FLOOR and floor_seen_in_footprint(lo, hi, cloud) >= CABINET_FLOOR_SHARE


def part_of_furniture(surface: Element, boxes: Sequence[tuple[np.ndarray, np.ndarray]]) -> bool:
    """Rule "seat or top": a level with PART_SHARE of its footprint inside the box of a
    floor-standing object, at a height within that box (FURNITURE_MARGIN_M of slack), is that
    object's seat or top."""
    area = float(np.prod(np.maximum(surface.hi[:2] - surface.lo[:2], 1e-3)))
    for lo, hi in boxes:
        if not lo[2] - FURNITURE_MARGIN_M <= surface.height <= hi[2] + FURNITURE_MARGIN_M:
            continue
        inter = np.clip(np.minimum(hi[:2], surface.hi[:2]) - np.maximum(lo[:2], surface.lo[:2]), 0, None)
        if float(np.prod(inter)) / area >= PART_SHARE:
            return True
    return False


def desk_shaped(height: float, area: float, floor_share: float) -> bool:
    """Rule "desk": a top DESK_TOP_HEIGHT above the floor, at least DESK_MIN_AREA, with knee
    space below (the floor seen under KNEE_FLOOR_SHARE of it)."""
    return (DESK_TOP_HEIGHT[0] <= height <= DESK_TOP_HEIGHT[1] and area >= DESK_MIN_AREA
            and floor_share >= KNEE_FLOOR_SHARE)


def cabinet_shaped(height: float, floor_share: float) -> bool:
    """Rule "cabinet": a top lower than a table's (below DESK_TOP_HEIGHT) that hides the floor
    under it (seen under less than CABINET_FLOOR_SHARE) is a solid box to the floor."""
    return height < DESK_TOP_HEIGHT[0] and floor_share < CABINET_FLOOR_SHARE


def surface_area(surface: Element) -> float:
    assert surface.footprint is not None
    return float(surface.footprint.sum()) * SURFACE_CELL_M ** 2


def renamed_by_shape(obj: ObjectObservation, label: str) -> ObjectObservation:
    """The object under the name its shape gives, the detector's labels kept after it."""
    labels = [label] + [x for x in obj.labels if x != label]
    scores = [obj.scores[0]] + [s for x, s in zip(obj.labels, obj.scores) if x != label]
    return replace(obj, labels=labels, scores=scores, named_by="shape")


def panel_fill(surface: Element, cloud: RoomCloud, h_lo: float, h_hi: float) -> np.ndarray:
    """Per slice along the top's long axis (SURFACE_CELL_M), the share of its (across, height)
    cells over the top's footprint extent that hold points with h_lo < h < h_hi."""
    assert surface.footprint is not None and surface.origin is not None
    along = int(np.argmax(surface.footprint.shape))
    n = np.array(surface.footprint.shape)
    p = cloud.points
    cells = np.floor((p[:, :2] - surface.origin) / SURFACE_CELL_M).astype(int)
    keep = (cells >= 0).all(axis=1) & (cells < n).all(axis=1) & (p[:, 2] > h_lo) & (p[:, 2] < h_hi)
    rows = int(np.ceil((h_hi - h_lo) / SURFACE_CELL_M))
    level = np.clip(((p[keep, 2] - h_lo) / SURFACE_CELL_M).astype(int), 0, rows - 1)
    occupied = np.zeros((n[along], n[1 - along], rows), bool)
    occupied[cells[keep, along], cells[keep, 1 - along], level] = True
    return occupied.reshape(n[along], -1).mean(axis=1)


def panel_cuts(surface: Element, cloud: RoomCloud) -> list[int]:
    """Rule "desks between panels": the slices (cell indices along the long axis) where a
    vertical panel crosses the top, above and below it (PANEL_MIN_FILL), each the fullest
    within PANEL_WINDOW_M and leaving desks of at least DESK_MIN_WIDTH on both sides."""
    above = panel_fill(surface, cloud, surface.height + SURFACE_CELL_M, surface.height + PANEL_REACH_M)
    below = panel_fill(surface, cloud, PANEL_FLOOR_GAP_M, surface.height - 2 * SURFACE_CELL_M)
    both = np.minimum(above, below)
    window, min_cells = int(round(PANEL_WINDOW_M / SURFACE_CELL_M)), int(round(DESK_MIN_WIDTH / SURFACE_CELL_M))
    assert surface.footprint is not None
    along = int(np.argmax(surface.footprint.shape))
    occupied = np.flatnonzero(surface.footprint.any(axis=1 - along))
    first, end = int(occupied[0]), int(occupied[-1]) + 1
    cuts: list[int] = []
    for k in range(first + min_cells, end - min_cells + 1):
        if both[k] >= PANEL_MIN_FILL and both[k] == both[max(0, k - window):k + window + 1].max() \
                and (not cuts or k - cuts[-1] >= min_cells):
            # the fullest slice of its window; a panel seen from both sides fills two slices
            cuts.append(k)
    return cuts


def split_at_panels(surface: Element, cloud: RoomCloud) -> list[Element]:
    """The desks of one worktop: the surface cut at `panel_cuts` (the surface itself when none)."""
    cuts = panel_cuts(surface, cloud)
    if not cuts:
        return [surface]
    assert surface.footprint is not None and surface.origin is not None
    along = int(np.argmax(surface.footprint.shape))
    parts = []
    for start, stop in zip([0] + cuts, cuts + [surface.footprint.shape[along]]):
        fp = np.zeros_like(surface.footprint)
        sl = [slice(None), slice(None)]
        sl[along] = slice(start, stop)
        fp[tuple(sl)] = surface.footprint[tuple(sl)]
        if not fp.any():
            continue
        ij = np.argwhere(fp)
        lo, hi = surface.lo.copy(), surface.hi.copy()
        lo[:2] = surface.origin + ij.min(axis=0) * SURFACE_CELL_M
        hi[:2] = surface.origin + (ij.max(axis=0) + 1) * SURFACE_CELL_M
        parts.append(replace(surface, lo=lo, hi=hi, footprint=fp, _grown=None))
    return parts


def box_with_top(lo: np.ndarray, hi: np.ndarray, top: Element) -> tuple[np.ndarray, np.ndarray]:
    """A solid piece of furniture's whole box: its box grown to its top's footprint, from the
    floor to the top (a detector boxed only the part of a sideboard it saw)."""
    lo2 = np.minimum(lo, np.array([top.lo[0], top.lo[1], 0.0]))
    hi2 = np.maximum(hi, np.array([top.hi[0], top.hi[1], top.height]))
    lo2[2], hi2[2] = 0.0, top.height
    return lo2, hi2


def desk_box(surface: Element) -> tuple[np.ndarray, np.ndarray]:
    """A desk's whole box: its top's footprint from the floor to the top."""
    lo = np.array([surface.lo[0], surface.lo[1], 0.0])
    hi = np.array([surface.hi[0], surface.hi[1], surface.height])
    return lo, hi


def desk_node(local_id: str, surface: Element, cloud: RoomCloud,
              as_object: Callable[[str, np.ndarray, np.ndarray, np.ndarray], ObjectObservation]) -> ObjectObservation:
    """A node named "desk" by its shape: its whole box, and the colour, histogram and thumbnail
    `as_object` reads from the top's points (world frame) as it does for any segment."""
    idx, _ = footprint_cells(surface, cloud.points)
    top = idx[np.abs(cloud.points[idx, 2] - surface.height) <= 0.03]
    lo, hi = desk_box(surface)
    obj = as_object(local_id, lo, hi, top)
    centre = cloud.to_world((lo + hi) / 2)
    return replace(obj, labels=[DESK_LABEL], scores=[1.0], size=vec3(hi - lo), box_centre=vec3(centre),
                   shape=None, named_by="shape")


def low_solid_top(obj: ObjectObservation, top: Optional[Element], cloud: RoomCloud) -> bool:
    """Whether a table-named object's own top says it is a cabinet (`cabinet_shaped`)."""
    return (obj.label in TABLE_LABELS and top is not None
            and cabinet_shaped(top.height, floor_seen_under(top, cloud)))


def back_or_arm_length(voxels: np.ndarray, seat_height: float) -> float:
    """How long a back or an arm a part (its voxels, gravity frame) is for a seat at `seat_height`:
    the length along its principal horizontal axis of its voxels COUCH_RISE_M above the seat, when
    it rises from the seat (its bottom at or below the seat level) and tops out by COUCH_MAX_TOP_M;
    0 otherwise."""
    if float(voxels[:, 2].min()) > seat_height or float(voxels[:, 2].max()) > COUCH_MAX_TOP_M:
        return 0.0
    up = voxels[voxels[:, 2] >= seat_height + COUCH_RISE_M, :2]
    if len(up) < 2:
        return 0.0
    centred = up - up.mean(axis=0)
    _, vecs = np.linalg.eigh(centred.T @ centred)
    return float(np.ptp(centred @ vecs[:, -1]))


def couch_shaped(seat_height: float, part_lengths: Sequence[float]) -> bool:
    """Rule "couch": a seat level COUCH_SEAT_HEIGHT above the floor with a back or an arm beside it
    (`couch_parts`) at least COUCH_MIN_PART_M long (`back_or_arm_length`): longer than any chair's
    back or arm, so wider than a chair."""
    return (COUCH_SEAT_HEIGHT[0] <= seat_height <= COUCH_SEAT_HEIGHT[1]
            and any(length >= COUCH_MIN_PART_M for length in part_lengths))


_touching = boxes_touch


def couch_parts(seat: Element, parts: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[int]:
    """The parts (gravity boxes lo, hi) of the seat's couch: those within COUCH_JOIN_M of the seat's
    footprint box, not lower than the floor's clutter and topping out by COUCH_MAX_TOP_M (its back,
    arms and cushions; a cabinet or a wall beside it is taller)."""
    return [k for k, (lo, hi) in enumerate(parts)
            if float(hi[2]) <= COUCH_MAX_TOP_M and float(hi[2]) >= seat.height - COUCH_JOIN_M
            and _touching(seat.lo, seat.hi, lo, hi, COUCH_JOIN_M)]


def couch_box(seat: Element, parts: Sequence[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """A couch's whole box: its seat's footprint and its parts' boxes, from the floor up."""
    lo = np.minimum.reduce([seat.lo] + [p[0] for p in parts]).astype(float)
    hi = np.maximum.reduce([seat.hi] + [p[1] for p in parts]).astype(float)
    lo[2] = 0.0
    hi[2] = max(float(hi[2]), seat.height)
    return lo, hi


def couch_node(local_id: str, lo: np.ndarray, hi: np.ndarray, cloud: RoomCloud,
               as_object: Callable[[str, np.ndarray, np.ndarray, np.ndarray], ObjectObservation]) -> ObjectObservation:
    """A node named "couch" by its shape: its whole box (`couch_box`), and the colour, histogram and
    thumbnail `as_object` reads from the cloud's points inside it above the floor."""
    p = cloud.points
    idx = np.flatnonzero((p >= lo).all(axis=1) & (p <= hi).all(axis=1) & (p[:, 2] > FLOOR_SLAB_M))
    obj = as_object(local_id, lo, hi, idx)
    centre = cloud.to_world((lo + hi) / 2)
    return replace(obj, labels=[COUCH_LABEL], scores=[1.0], size=vec3(hi - lo), box_centre=vec3(centre),
                   shape=None, named_by="shape")


def base_under_seat(lo: np.ndarray, hi: np.ndarray, seats: Sequence[tuple[np.ndarray, np.ndarray]]) -> bool:
    """Rule "a seat's base": a piece (gravity box lo, hi) whose top is at most BASE_MAX_TOP_M above
    the floor and whose footprint overlaps the footprint of a seat standing above it, or lies within
    BASE_REACH_M of it (a base's legs reach beyond the seat's edge) (`seats`: a
    named floor-standing object's box, or a part whose bottom is at least SEAT_MIN_BOTTOM_M high)
    is that seat's base or legs (a chair's five-star base), not an object of its own."""
    if float(hi[2]) > BASE_MAX_TOP_M:
        return False
    return any(_touching(lo, hi, slo, shi, BASE_REACH_M) and float(shi[2]) > BASE_MAX_TOP_M for slo, shi in seats)
