"""Every object in the room: the named objects' whole boxes, the unnamed segments, the structure.

The detector names what it can; depth sees everything. After fusion (`sg3d.ingest.objects.fusion`) the
chunk's named objects meet the room's cloud (`sg3d.ingest.discover.room_cloud`), its structure
(`sg3d.ingest.discover.structure`) and its class-agnostic segments (`sg3d.ingest.discover.segments`):

- `outside.seen_through_wall`: a segment depth saw through a wall's glass or gap (all of it beyond
  a wall that bounds the room, seen through the wall's face: `outside.bounding_walls`) is outside
  the room, not an object;
- `whole_object_box`: a named object's box spans the object, not the part the detector boxed
  (rules "stands on the floor" and "owns its top");
- `named_by`: a segment that lies inside a named object's whole box is that object (its name is
  the detector's evidence, accumulated over views), and is not a node of its own; so is a piece
  just beyond a named box that the box stopped short of (`own_edge`: a screen's rim);
- `separate_resting`: things lying side by side on a table, a counter or a shelf touch; a
  segment resting on a surface is cut at its necks (`segments.split_at_necks`), or with no neck
  at a colour edge (`segments.split_at_colour_edge`: a red gamepad against a white box);
- `plane_remnant`: a thin relief left along a cut wall or front (a door edge) is not an object,
  nor is a flat piece lying on the floor (`floor_remnant`) or one under a surface's level, its
  board's thickness (`board_of_surface`);
- `row_parts`: a kept segment longer than one thing is a row of things standing side by side (on
  a shelf no surface rule found, against a wall) and is cut at its necks too;
- `face_part`: a floor-standing detection (a "chair") whose box lies inside a kept face twice as
  long as it is a detection of part of that face (a bed's side seen from low), not an object: it
  leaves the named objects;
- `separate_at_walls`: a segment welded along a wall no structure rule found (a far wall whose
  normals were too noisy to vote) is cut at that wall's plane (`segments.split_at_wall`: the bins
  before a whiteboard's wall); what lies flat on or just behind such a wall is the wall's
  (`relief_of_found_wall`);
- `one_sheet`: tall pieces of one colour on one vertical plane, a fold's shadow apart, are one
  object (a curtain's folds);
- furniture from shape (`sg3d.ingest.discover.furniture`): desks (a worktop cut at its carrels'
  panels; what lies in the worktop's box and the thin panels beside it are the desks':
  `sg3d.core.geometry.carrel_panel`, which the merge applies to stored desks too), couches
  (a seat level with a back or an arm longer than a chair's: its parts are one node), and a low
  piece under a seat is that seat's base;
- `unnamed_object`: any other segment becomes a node labelled UNNAMED_LABEL, with its size,
  colour, thumbnail from the view that saw it best, and a shape word where the geometry says one
  (`shape_word`); it is never given a class name;
- `structure_node`: the floor, the walls and each surface no named object owns become
  structure-layer nodes.
"""
from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Callable, Iterable, Optional, Sequence

import cv2
import numpy as np

from sg3d.core.geometry import FLOOR_STANDING_LABELS
from sg3d.core.model import HIST_SIZE, UNNAMED_LABEL, ObjectObservation, vec3
from sg3d.ingest.discover import flat_things, furniture, outside, shelves
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.segments import (
    GOOD_VIEWS,
    RESTING_M,
    VOXEL_M,
    WELD_MIN_EXTENT_M,
    WELD_PLANE_SLAB_M,
    Segment,
    depth_evidence,
    exists,
    room_candidates,
    split_at_colour_edge,
    split_at_necks,
    split_at_wall,
    welded_wall,
)
from sg3d.ingest.discover.structure import SURFACE_SLAB_M, Element
from sg3d.ingest.objects import colour as colour_model
from sg3d.ingest.objects.attributes import hsv_histogram, thumbnail

if TYPE_CHECKING:
    from sg3d.ingest.objects.existence import View

# Furniture whose top is a surface others stand on (a chair tucked under a table does not own
# the table's top).
TOP_OWNERS = ("dining table", "desk", "bench", "bed")
# A named object owns a surface when the surface covers this share of the object's footprint
# and lies within TOP_TOLERANCE_M of the object's box in height (a table and its top).
OWN_FOOTPRINT_SHARE = 0.5
TOP_TOLERANCE_M = 0.15
# A segment is a named object's when this share of its voxels lies inside that object's whole
# box grown by NAMED_MARGIN_M.
NAMED_SHARE = 0.5
NAMED_MARGIN_M = 0.02
# A detector's box may stop short of its object's edge (a screen's bezel above the box) by up to
# EDGE_GROWTH of its side: a piece with NAMED_SHARE of its voxels inside the box grown so is
# that object's edge (`own_edge`).
EDGE_GROWTH = 0.25
# A plane remnant (a relief of a cut wall or front): its median voxel lies within
# REMNANT_DISTANCE_M of the plane and it is at most REMNANT_THICKNESS_M thick across it. Depth at
# room range (1-3 cm noise, cut at PLANE_CUT_M) cannot tell trim, a door edge or a poster
# that stands out less than that from the plane it is on.
REMNANT_DISTANCE_M = 0.07
REMNANT_THICKNESS_M = 0.12
# A wall found inside a welded segment (`segments.split_at_wall`) is placed only to the width of
# the slab its plane was voted in (segments.WELD_PLANE_SLAB_M: the board on it may be the plane
# found, the wall then lies behind it), so what lies behind it is its own within that much more.
FOUND_WALL_DISTANCE_M = REMNANT_DISTANCE_M + WELD_PLANE_SLAB_M
# Part of the floor: a piece whose top is this low and that is this thin.
FLOOR_REMNANT_TOP_M = 0.10
FLOOR_REMNANT_THICKNESS_M = 0.06
# A segment hovering with its bottom up to this high is a seat (chairs' and couches' seats stand
# at 0.35-0.50 m; with its cushion's underside hidden a seat's bottom shows a little lower).
SEAT_MAX_BOTTOM_M = 0.60
# What holds a top up stands on the floor (its foot at most LEG_FOOT_M above it: a leg's glide,
# a plinth) and reaches the top's underside: its highest voxel at most LEG_REACH_M below the
# top's level (the board's thickness, 2-4 cm, the surface slab cut away with it, SURFACE_SLAB_M,
# and a voxel), with LEG_UNDER_SHARE of its voxels under the top's footprint. Nothing else
# spans from the floor to a top's underside: a chair's back rises past it, a box under a table
# stops short of it, and a book on a shelf board does not stand on the floor.
LEG_FOOT_M = 0.10
LEG_REACH_M = 0.08
LEG_UNDER_SHARE = 0.5
# Shape words: flat when the height is at most FLAT_RATIO of the larger horizontal side; tall
# when at least TALL_RATIO times it; box-shaped when the three sides are within BOX_RATIO of
# each other and the points fill the box's faces.
FLAT_RATIO = 0.25
TALL_RATIO = 2.0
BOX_RATIO = 2.5
VOXEL_VAR_FLOOR = 0.01 ** 2
# Surface points kept per unnamed object for re-scans (`sg3d.ingest.objects.rescan.surface_seen_empty`).
SURFACE_SAMPLE = 32
# A screen's box side this close to the image border (share of the image size) reaches it.
SCREEN_BORDER_SHARE = 0.05
# The half-width a voxel covers, for marking a segment's own pixels.
VOXEL_DISC_M = 0.0125
# One hanging or standing sheet (a curtain, a door leaf, a panel) comes apart in depth along its
# folds and the shadows between them: two tall pieces (`shape_word` "tall") of one colour whose
# footprints lie within REJOIN_GAP_M of each other (a fold's shadow: a few cm; things placed side by
# side stand farther apart or touch), that share REJOIN_HEIGHT_SHARE of the shorter one's height
# and whose voxels together lie on one vertical plane (at most REJOIN_MAX_THICKNESS_M across their
# principal horizontal axis: a curtain's folds stand 10-15 cm deep) are one object.
REJOIN_GAP_M = 0.10
REJOIN_HEIGHT_SHARE = 0.5
REJOIN_MAX_THICKNESS_M = 0.20
# A detection of part of a face (`face_part`): its box lies inside the face's box grown by
# FACE_PART_MARGIN_M (the floor's slab, FLOOR_SLAB_M, is cut from every segment, so a face's box
# starts a voxel above it while a floor-standing object's box reaches the floor), and the face
# is at least FACE_PART_RATIO times as long as the box is wide.
FACE_PART_MARGIN_M = 0.05
FACE_PART_RATIO = 2.0


def gravity_box(obj: ObjectObservation, cloud: RoomCloud) -> tuple[np.ndarray, np.ndarray]:
    """An object's box in the cloud's gravity frame (h above the floor)."""
    c = cloud.basis @ np.asarray(obj.box_centre if obj.box_centre is not None else obj.mean, float)
    c[2] -= cloud.floor
    half = np.asarray(obj.size, float) / 2
    return c - half, c + half


def owned_surface(lo: np.ndarray, hi: np.ndarray, surfaces: Sequence[Element]) -> Optional[Element]:
    """Rule "owns its top": the horizontal surface covering OWN_FOOTPRINT_SHARE of the box's
    footprint whose level lies within TOP_TOLERANCE_M of the box's height range (the most
    covering one), or None."""
    area = float(np.prod(np.maximum(hi[:2] - lo[:2], 1e-3)))
    best, best_share = None, OWN_FOOTPRINT_SHARE
    for e in surfaces:
        if e.footprint is None or not (lo[2] - TOP_TOLERANCE_M <= e.height <= hi[2] + TOP_TOLERANCE_M):
            continue
        inter = np.clip(np.minimum(hi[:2], e.hi[:2]) - np.maximum(lo[:2], e.lo[:2]), 0, None)
        share = float(np.prod(inter)) / area
        if share >= best_share:
            best, best_share = e, share
    return best


def whole_object_box(obj: ObjectObservation, cloud: RoomCloud, surfaces: Sequence[Element]) -> Optional[Element]:
    """Rules "stands on the floor" and "owns its top": floor-standing furniture
    (FLOOR_STANDING_LABELS: tables, chairs, couches ...) reaches down to the floor, and a
    table, desk, bench or bed (TOP_OWNERS) whose footprint a horizontal surface covers has
    that surface as its top: the top ends it in height (what stands on a table does not make it
    taller) and spans it (one rigid board: a detector that boxed the part of a desk it saw from
    two frames saw part of the desk). Updates `obj.size`/`box_centre` and returns the surface it
    owns (None when it owns none)."""
    if obj.label not in FLOOR_STANDING_LABELS:
        return None
    lo, hi = gravity_box(obj, cloud)
    lo[2] = 0.0
    top = owned_surface(lo, hi, surfaces) if obj.label in TOP_OWNERS else None
    if top is not None:
        hi[2] = top.height
        lo[:2] = np.minimum(lo[:2], top.lo[:2])
        hi[:2] = np.maximum(hi[:2], top.hi[:2])
    hi[2] = max(hi[2], lo[2] + 0.05)
    obj.size = vec3(hi - lo)
    obj.box_centre = vec3(cloud.to_world((lo + hi) / 2))
    return top


def named_by(seg: Segment, boxes: Sequence[tuple[np.ndarray, np.ndarray]]) -> bool:
    """A segment with NAMED_SHARE of its voxels inside one named object's box (grown by
    NAMED_MARGIN_M) is that object."""
    for lo, hi in boxes:
        inside = ((seg.voxels >= lo - NAMED_MARGIN_M) & (seg.voxels <= hi + NAMED_MARGIN_M)).all(axis=1)
        if float(inside.mean()) >= NAMED_SHARE:
            return True
    return False


def own_edge(seg: Segment, boxes: Sequence[tuple[np.ndarray, np.ndarray]]) -> bool:
    """Rule "the named object's own edge": a detector's box may stop short of its object's edge
    by up to EDGE_GROWTH of the box's side on each axis (a screen's bezel, a frame's rim), and the
    box's points are claimed before segmentation, so that edge comes out as a piece hugging the
    box. A piece with NAMED_SHARE of its voxels inside one named object's box grown by
    EDGE_GROWTH of its sides, that does not stand on the box's top (its bottom below the box's
    top less RESTING_M: what stands on a thing is not its edge), is that object. The growth is
    relative to the box: a thing beside a small object lies outside it."""
    for lo, hi in boxes:
        grow = EDGE_GROWTH * (hi - lo)
        if float(seg.lo[2]) >= float(hi[2]) - RESTING_M:
            continue
        inside = ((seg.voxels >= lo - grow) & (seg.voxels <= hi + grow)).all(axis=1)
        if float(inside.mean()) >= NAMED_SHARE:
            return True
    return False


def plane_remnant(seg: Segment, planes: Sequence[Element]) -> bool:
    """Rule "relief of a plane": a segment whose median voxel lies within REMNANT_DISTANCE_M of
    a cut wall or front and that is at most REMNANT_THICKNESS_M thick across it (trim, door
    edges, a cabinet's side, a poster) is part of that plane, not an object of its own."""
    for e in planes:
        assert e.plane is not None      # `discover` passes the elements that have a plane
        theta, rho = e.plane
        off = seg.voxels[:, 0] * np.cos(theta) + seg.voxels[:, 1] * np.sin(theta) - rho
        if float(np.median(np.abs(off))) <= REMNANT_DISTANCE_M and float(np.ptp(off)) <= REMNANT_THICKNESS_M:
            return True
    return False


def floor_remnant(seg: Segment) -> bool:
    """Rule "part of the floor": a flat piece lying on the floor (its top at most
    FLOOR_REMNANT_TOP_M above it, at most FLOOR_REMNANT_THICKNESS_M thick) is the floor's own
    unevenness or a covering's edge: depth at room range cannot tell it from the floor."""
    return float(seg.hi[2]) <= FLOOR_REMNANT_TOP_M and float(seg.size[2]) <= FLOOR_REMNANT_THICKNESS_M


def resting_on(seg: Segment, surfaces: Sequence[Element]) -> bool:
    """A segment rests on a horizontal surface when its bottom lies within RESTING_M of the
    surface's level and its centre above the surface's footprint."""
    centre = np.array([[*((seg.lo[:2] + seg.hi[:2]) / 2), 0.0]])
    for e in surfaces:
        if abs(float(seg.lo[2]) - e.height) <= RESTING_M:
            centre[0, 2] = e.height
            if bool(e.contains(centre, RESTING_M)[0]):
                return True
    return False


def holds_up_top(seg: Segment, surfaces: Sequence[Element]) -> bool:
    """Rule "what holds a top up": a segment whose foot lies at most LEG_FOOT_M above the floor,
    whose top lies within LEG_REACH_M below a horizontal surface's level (and not above it), and
    with LEG_UNDER_SHARE of its voxels under that surface's footprint is the surface's legs,
    sides or pedestal: part of the furniture the top belongs to, not a thing of its own."""
    if float(seg.lo[2]) > LEG_FOOT_M:
        return False
    top = float(seg.hi[2])
    for e in surfaces:
        if not e.height - LEG_REACH_M <= top <= e.height:
            continue
        lifted = seg.voxels.copy()
        lifted[:, 2] = e.height
        if float(e.contains(lifted, RESTING_M).mean()) >= LEG_UNDER_SHARE:
            return True
    return False


def board_of_surface(seg: Segment, surfaces: Sequence[Element]) -> bool:
    """Rule "the board's own thickness": a flat piece (`shape_word`) whose top lies within
    RESTING_M of a horizontal surface's level and whose centre lies under the surface's footprint
    is that surface's board (a worktop's thickness or front lip below the slab cut away as the
    surface, a table's apron), not a thing: things stand on a surface, their bottoms at its level."""
    if shape_word(seg.size) != "flat":
        return False
    centre = np.array([[*((seg.lo[:2] + seg.hi[:2]) / 2), 0.0]])
    for e in surfaces:
        if abs(float(seg.hi[2]) - e.height) <= RESTING_M:
            centre[0, 2] = e.height
            if bool(e.contains(centre, RESTING_M)[0]):
                return True
    return False


def voxel_chroma(seg: Segment, cloud: RoomCloud, colour_image: Callable[[int], Optional[np.ndarray]]) -> np.ndarray:
    """The CIELAB chroma (a*, b*) of each of a segment's voxels read at its centre's pixel in the
    segment's best good view (`segments.GOOD_VIEWS`); NaN where that view does not show it (or
    there is no good view or image)."""
    out = np.full((len(seg.voxels), 2), np.nan)
    image = colour_image(cloud.views[seg.good_views[0]].index) if seg.good_views else None
    if image is None:
        return out
    view = cloud.views[seg.good_views[0]]
    cam = _to_camera(cloud.to_world(seg.voxels), view)
    z = np.maximum(cam[:, 2], 1e-6)
    u = np.round(view.K[0, 0] * cam[:, 0] / z + view.K[0, 2]).astype(int)
    v = np.round(view.K[1, 1] * cam[:, 1] / z + view.K[1, 2]).astype(int)
    h, w = image.shape[:2]
    seen = (cam[:, 2] > 0.1) & (u >= 0) & (u < w) & (v >= 0) & (v < h)
    if seen.any():
        out[seen] = colour_model.bgr_to_lab(image[v[seen], u[seen]])[:, 1:]
    return out


def separate_resting(segments: Sequence[Segment], surfaces: Sequence[Element], cloud: RoomCloud,
                     colour_image: Optional[Callable[[int], Optional[np.ndarray]]] = None) -> list[Segment]:
    """Things lying side by side on a table, a counter or a shelf touch: a segment resting on a
    surface is cut at its necks (`segments.split_at_necks`), or, with no neck, at a colour edge
    between two things of two colours (`segments.split_at_colour_edge` on its voxels' colours in
    its best view, `voxel_chroma`), before depth judges it, and each part must pass the depth
    existence test on its own (a dark gamepad that depth sees through does not take the white
    box it lies against with it); other segments are judged whole."""
    out: list[Segment] = []
    for seg in segments:
        resting = resting_on(seg, surfaces)
        parts = split_at_necks(seg) if resting else [seg]
        if resting and colour_image is not None and len(parts) == 1:
            parts = split_at_colour_edge(seg, voxel_chroma(seg, cloud, colour_image))
        for part in parts:
            if part is not seg:
                part.on_board = seg.on_board
                depth_evidence(part, cloud)
            if exists(part):
                out.append(part)
    return out


def separate_shelf_contents(segments: Sequence[Segment], surfaces: Sequence[Element], cloud: RoomCloud) -> list[Segment]:
    """What stands on a bookcase's boards comes off the bookcase (`shelves.split_frame`); each
    part carries its own depth evidence (`depth_evidence`) and is judged by it later."""
    out: list[Segment] = []
    cams = np.array([v.pose[:3, 3] for v in cloud.views]) @ cloud.basis.T
    toward = cams[:, :2].mean(axis=0) if len(cams) else np.zeros(2)
    for seg in segments:
        parts = shelves.split_frame(seg, surfaces, toward)
        if len(parts) > 1:
            for part in parts:
                depth_evidence(part, cloud)
        out.extend(parts)
    return out


def separate_at_walls(segments: Sequence[Segment], cloud: RoomCloud) -> tuple[list[Segment], list[Element]]:
    """Segments welded along a wall no structure rule found are cut there
    (`segments.split_at_wall`); each part must pass the depth existence test on its own. Returns
    the segments and the walls found so, each as a wall element (its plane, the box of its
    plane's piece)."""
    out: list[Segment] = []
    found: list[Element] = []
    for seg in segments:
        wall = welded_wall(seg)
        parts = split_at_wall(seg, wall) if wall is not None else [seg]
        if wall is None or len(parts) == 1:
            out.append(seg)
            continue
        th, rho = wall[0], wall[1]
        # the room's side of the wall: where the cameras stand
        cams = np.array([v.pose[:3, 3] for v in cloud.views]) @ cloud.basis.T
        side = float(np.sign(np.median(cams[:, 0] * np.cos(th) + cams[:, 1] * np.sin(th)) - rho)) or 1.0
        found.append(Element("wall", parts[0].lo, parts[0].hi, len(parts[0].voxels), len(seg.frames),
                             plane=(th, rho), side=side))
        for part in parts:
            depth_evidence(part, cloud)
            if exists(part):
                out.append(part)
    return out, found


def row_parts(seg: Segment, cloud: RoomCloud) -> list[Segment]:
    """Rule "a row of things": a segment at least `segments.WELD_MIN_EXTENT_M` across in the top
    view is longer than one thing standing on its own (chairs up to 1.1 m; couches and desks are
    taken before), so it holds things standing side by side, on a board no surface rule found (a
    wall shelf's top hidden by what stands on it) or against a wall: it is cut at its necks
    (`segments.split_at_necks`) like a segment resting on a surface, and each part that passes the
    depth existence test on its own is returned. The row stood out of every plane more than a
    relief (`plane_remnant`), so its parts are the things standing against it, not relief (a
    booklet upright against the wall beside a mouse). A shorter segment, or one without necks, is
    returned whole."""
    if float(np.max(seg.size[:2])) < WELD_MIN_EXTENT_M:
        return [seg]
    parts = split_at_necks(seg)
    if len(parts) == 1:
        return [seg]
    for part in parts:
        depth_evidence(part, cloud)
    return [part for part in parts if exists(part)]


def face_part(lo: np.ndarray, hi: np.ndarray, seg: Segment) -> bool:
    """Rule "a detection of part of a face": a named floor-standing object's box (lo, hi) that lies
    inside a kept segment's box grown by FACE_PART_MARGIN_M, where that segment lies on one
    vertical plane (`plane_thickness` at most REJOIN_MAX_THICKNESS_M) and is at least
    FACE_PART_RATIO times as long as the box is wide, named part of that face: one body's side (a
    bed's side seen from a robot's height, which the detector calls a chair), not a thing standing
    there. A thing standing before a face is deeper than the face's slab; the face stays the
    object."""
    if not (np.all(lo >= seg.lo - FACE_PART_MARGIN_M) and np.all(hi <= seg.hi + FACE_PART_MARGIN_M)):
        return False
    if float(np.max(seg.size[:2])) < FACE_PART_RATIO * float(np.max(hi[:2] - lo[:2])):
        return False
    return plane_thickness(seg.voxels) <= REJOIN_MAX_THICKNESS_M


def relief_of_found_wall(seg: Segment, walls: Sequence[Element]) -> bool:
    """Rule "relief of a plane" (`plane_remnant`) for the walls found in welded segments
    (`separate_at_walls`): a segment whose median voxel lies within REMNANT_DISTANCE_M of such a
    wall's plane on the room's side (what stands on a counter against it is not the wall), or
    within FOUND_WALL_DISTANCE_M behind it, at most REMNANT_THICKNESS_M thick across it and near
    the piece of wall seen (its box grown by REJOIN_GAP_M: the wall's extent is known only there)
    is part of the wall. The wall's own piece is no relief of itself."""
    for e in walls:
        assert e.plane is not None
        if (np.array_equal(seg.lo, e.lo) and np.array_equal(seg.hi, e.hi)
                or not furniture.boxes_touch(seg.lo, seg.hi, e.lo, e.hi, REJOIN_GAP_M)
                or float(seg.lo[2]) > float(e.hi[2]) + REJOIN_GAP_M or float(seg.hi[2]) < float(e.lo[2]) - REJOIN_GAP_M):
            continue
        theta, rho = e.plane
        off = e.side * (seg.voxels[:, 0] * np.cos(theta) + seg.voxels[:, 1] * np.sin(theta) - rho)
        reach = FOUND_WALL_DISTANCE_M if float(np.median(off)) < 0 else REMNANT_DISTANCE_M
        if float(np.median(np.abs(off))) <= reach and float(np.ptp(off)) <= REMNANT_THICKNESS_M:
            return True
    return False


def shape_word(size: Iterable[float]) -> Optional[str]:
    """Rule "shape word" from a gravity-aligned size (w, d, h): flat, tall or box-shaped (see
    FLAT_RATIO, TALL_RATIO, BOX_RATIO); None when none fits. Roundness is not judged from a box."""
    w, d, h = (float(v) for v in size)
    side = max(w, d)
    if h <= FLAT_RATIO * side:
        return "flat"
    if h >= TALL_RATIO * side:
        return "tall"
    if max(w, d, h) <= BOX_RATIO * max(min(w, d, h), 1e-3):
        return "box-shaped"
    return None


def _to_camera(world: np.ndarray, view: View) -> np.ndarray:
    """World points in a view's camera frame (z forward)."""
    w2c = np.linalg.inv(view.pose)
    return world @ w2c[:3, :3].T + w2c[:3, 3]


def _project(world: np.ndarray, view: View) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixel coordinates (u, v) and camera depth z of the world points in front of a view."""
    cam = _to_camera(world, view)
    cam = cam[cam[:, 2] > 0.1]
    K = view.K
    return K[0, 0] * cam[:, 0] / cam[:, 2] + K[0, 2], K[1, 1] * cam[:, 1] / cam[:, 2] + K[1, 2], cam[:, 2]


def _pixels(u: np.ndarray, v: np.ndarray, view: View) -> Optional[tuple[int, int, int, int]]:
    """The pixel box (x1, y1, x2, y2) of projected points, clipped to the image; None when empty."""
    if len(u) == 0:
        return None
    w, h = view.size
    x1, x2 = int(max(0, np.floor(u.min()))), int(min(w, np.ceil(u.max()) + 1))
    y1, y2 = int(max(0, np.floor(v.min()))), int(min(h, np.ceil(v.max()) + 1))
    if x2 - x1 < 2 or y2 - y1 < 2:
        return None
    return x1, y1, x2, y2


def surface_sample(world: np.ndarray, n: int = SURFACE_SAMPLE) -> tuple[float, ...]:
    """Up to `n` of a segment's voxel centres (world frame, evenly through their order), flat:
    the points a re-scan tests for free space."""
    pick = world[np.linspace(0, len(world) - 1, min(n, len(world))).round().astype(int)]
    return tuple(round(float(v), 4) for v in pick.reshape(-1))


def screens_in_view(screens: Sequence[tuple[np.ndarray, np.ndarray]], cloud: RoomCloud,
                    view: View) -> list[tuple[int, int, int, int]]:
    """The pixel boxes in a view of the named screens' gravity-frame boxes (lo, hi): the box of
    each one's projected corners (`_pixels`), those in front of the camera; a side within
    SCREEN_BORDER_SHARE of the image border runs to it (the screen was seen cut there, so its
    3-D box stops short of its edge)."""
    out = []
    w, h = view.size
    mx, my = SCREEN_BORDER_SHARE * w, SCREEN_BORDER_SHARE * h
    for lo, hi in screens:
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        u, v, _ = _project(cloud.to_world(corners), view)
        box = _pixels(u, v, view)
        if box is not None:
            x1, y1, x2, y2 = box
            # a screen seen only cut by the image border is measured short on that side
            out.append((0 if x1 <= mx else x1, 0 if y1 <= my else y1,
                        w if x2 >= w - mx else x2, h if y2 >= h - my else y2))
    return out


def voxel_discs(u: np.ndarray, v: np.ndarray, z: np.ndarray, focal: float, shape: tuple[int, ...]) -> np.ndarray:
    """The pixels projected voxels cover (uint8 mask of `shape`): each voxel a filled disc at its
    rounded pixel (u, v) of radius max(1, round(focal * VOXEL_DISC_M / z)), exactly as
    `cv2.circle` draws it, parts off the image dropped. Drawn one radius at a time as a dilation
    of that radius's centres by the disc (the same union, without a Python loop over voxels: a
    segment's 3,000 voxels took 10 ms one circle at a time, 1 ms this way)."""
    h, w = shape[:2]
    mask = np.zeros((h, w), np.uint8)
    cx = np.round(np.asarray(u, dtype=np.float64)).astype(np.int64)
    cy = np.round(np.asarray(v, dtype=np.float64)).astype(np.int64)
    r = np.maximum(1, np.round(focal * VOXEL_DISC_M / np.asarray(z, dtype=np.float64)).astype(np.int64))
    keep = (cx + r >= 0) & (cx - r < w) & (cy + r >= 0) & (cy - r < h)
    if not keep.any():
        return mask
    cx, cy, r = cx[keep], cy[keep], r[keep]
    R = int(r.max())
    x0, y0 = int(cx.min()) - R, int(cy.min()) - R        # the canvas: the discs' bounding box
    canvas = np.zeros((int(cy.max()) - y0 + R + 1, int(cx.max()) - x0 + R + 1), np.uint8)
    for radius in np.unique(r):
        centres = np.zeros_like(canvas)
        sel = r == radius
        centres[cy[sel] - y0, cx[sel] - x0] = 1
        disc = np.zeros((2 * int(radius) + 1, 2 * int(radius) + 1), np.uint8)
        cv2.circle(disc, (int(radius), int(radius)), int(radius), 1, -1)
        np.bitwise_or(canvas, cv2.dilate(centres, disc), out=canvas)
    ys, xs = max(0, y0), max(0, x0)
    ye, xe = min(h, y0 + canvas.shape[0]), min(w, x0 + canvas.shape[1])
    mask[ys:ye, xs:xe] = canvas[ys - y0:ye - y0, xs - x0:xe - x0]
    return mask


def segment_reading(projected: tuple[np.ndarray, np.ndarray, np.ndarray], view: View, image: np.ndarray,
                    box: tuple[int, int, int, int],
                    screens: Sequence[tuple[int, int, int, int]] = ()) -> Optional[colour_model.ColourReading]:
    """One view's colour reading of a segment from its own pixels: its projected voxel centres
    (`projected` = u, v, z of `_project`), each marking the disc a voxel covers there, read with the cast of the light
    around its pixel box divided out (`sg3d.ingest.objects.colour.surround_cast`, the pixel boxes of the
    `screens` in view left out; `read_colour`), as for named objects. None without pixels."""
    u, v, z = projected
    mask = voxel_discs(u, v, z, float(view.K[0, 0]), image.shape[:2])
    pixels = image[mask > 0]
    if len(pixels) == 0:
        return None
    return colour_model.read_colour(pixels, colour_model.surround_cast(image, box, emitters=screens))


def segment_colour(seg: Segment, world: np.ndarray, cloud: RoomCloud,
                   colour_image: Callable[[int], Optional[np.ndarray]],
                   screens: Sequence[tuple[np.ndarray, np.ndarray]] = ()) -> tuple[str, Optional[str]]:
    """(colour, second colour) of a segment: its readings in its good views (`segment_reading`,
    up to `segments.GOOD_VIEWS` that show most of it), voted with weights by how many of its pixels
    each view shows (`sg3d.ingest.objects.colour.vote`, `view_weight`): one view's light or a screen beside it
    does not name the object alone."""
    readings, weights = [], []
    for k in seg.good_views:
        view = cloud.views[k]
        u, v, z = _project(world, view)
        box = _pixels(u, v, view)
        image = colour_image(view.index) if box is not None else None
        if image is None:
            continue
        assert box is not None          # an image is read only for a view with a pixel box
        reading = segment_reading((u, v, z), view, image, box, screens_in_view(screens, cloud, view))
        if reading is not None:
            readings.append(reading)
            weights.append(colour_model.view_weight(reading.n, 1.0, False))
    if not readings:
        return "grey", None
    name, second, _ = colour_model.vote(readings, weights)
    return name, second


def unnamed_object(local_id: str, seg: Segment, cloud: RoomCloud,
                   colour_image: Callable[[int], Optional[np.ndarray]],
                   screens: Sequence[tuple[np.ndarray, np.ndarray]] = ()) -> ObjectObservation:
    """A node for a segment no detector named: label UNNAMED_LABEL, its voxels' Gaussian (Eq. 8
    moments over the surface it showed), its box, the colour of its own pixels over its good
    views (`segment_colour`; the named `screens`' gravity boxes left out of the light's estimate)
    and the histogram (Eq. 9) and thumbnail of its box in the view that saw it best; score = the
    share of its voxels that are solid (`sg3d.ingest.discover.segments.depth_evidence`)."""
    world = cloud.to_world(seg.voxels)
    mean = world.mean(axis=0)
    var = np.maximum(world.var(axis=0), VOXEL_VAR_FLOOR)
    hist, thumb = np.zeros(HIST_SIZE), None
    frames = [int(cloud.views[k].index) for k in seg.frames]
    if seg.best_view >= 0:
        view = cloud.views[seg.best_view]
        u, v, _ = _project(world, view)
        box = _pixels(u, v, view)
        image = colour_image(view.index) if box is not None else None
        if image is not None:
            hist = hsv_histogram(image, box)
            thumb = thumbnail(image, box)
    colour, colour2 = segment_colour(seg, world, cloud, colour_image, screens)
    return ObjectObservation(
        local_id=local_id, labels=[UNNAMED_LABEL], scores=[round(seg.hit_ratio, 3)],
        mean=vec3(mean), var=vec3(var), n_points=len(seg.voxels),
        size=vec3(seg.size), hist=hist, colour=colour, colour2=colour2, thumbnail=thumb,
        first_frame=min(frames) if frames else 0, last_frame=max(frames) if frames else 0,
        n_frames=max(1, seg.seen_views), box_centre=vec3(cloud.to_world((seg.lo + seg.hi) / 2)),
        shape=shape_word(seg.size), surface=surface_sample(world))


def plane_thickness(voxels: np.ndarray) -> float:
    """The extent of voxels (gravity frame) across their principal horizontal axis: how far they
    lie from one vertical plane."""
    xy = voxels[:, :2] - voxels[:, :2].mean(axis=0)
    if len(xy) < 2:
        return 0.0
    _, vecs = np.linalg.eigh(xy.T @ xy)
    return float(np.ptp(xy @ vecs[:, 0]))


def one_sheet(a: Segment, b: Segment, colour_a: str, colour_b: str) -> bool:
    """Rule "one sheet, in pieces": two tall pieces (`shape_word`) of one colour, their footprints
    within REJOIN_GAP_M of each other, sharing REJOIN_HEIGHT_SHARE of the shorter one's height
    range, whose voxels together lie on one vertical plane (`plane_thickness` at most
    REJOIN_MAX_THICKNESS_M), are one object (a curtain's folds)."""
    if colour_a != colour_b or shape_word(a.size) != "tall" or shape_word(b.size) != "tall":
        return False
    if not furniture.boxes_touch(a.lo, a.hi, b.lo, b.hi, REJOIN_GAP_M):
        return False
    shared = min(float(a.hi[2]), float(b.hi[2])) - max(float(a.lo[2]), float(b.lo[2]))
    if shared < REJOIN_HEIGHT_SHARE * min(float(a.size[2]), float(b.size[2])):
        return False
    return plane_thickness(np.concatenate([a.voxels, b.voxels])) <= REJOIN_MAX_THICKNESS_M


def joined(a: Segment, b: Segment) -> Segment:
    """One segment of two (`one_sheet`): their voxels and frames, depth evidence summed, the
    views of the one seen better."""
    vox = np.concatenate([a.voxels, b.voxels])
    best = a if a.seen_views >= b.seen_views else b
    return Segment(vox, np.minimum(a.lo, b.lo), np.maximum(a.hi, b.hi), np.union1d(a.frames, b.frames),
                   hits=a.hits + b.hits, free=a.free + b.free, seen_views=max(a.seen_views, b.seen_views),
                   looked_views=max(a.looked_views, b.looked_views), best_view=best.best_view,
                   good_views=best.good_views)


def rejoin_sheets(pieces: list[tuple[Segment, ObjectObservation]], remake: Callable[[Segment], ObjectObservation],
                  ) -> list[tuple[Segment, ObjectObservation]]:
    """The unnamed pieces with those of one sheet (`one_sheet`) joined, each join a node made
    again (`remake`) from the joined segment, until no two pieces are one sheet."""
    out = list(pieces)
    merged = True
    while merged:
        merged = False
        for i in range(len(out)):
            for j in range(i + 1, len(out)):
                (a, oa), (b, ob) = out[i], out[j]
                if one_sheet(a, b, oa.colour, ob.colour):
                    seg = joined(a, b)
                    out[i] = (seg, remake(seg))
                    del out[j]
                    merged = True
                    break
            if merged:
                break
    return out


def points_object(local_id: str, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray, cloud: RoomCloud,
                  colour_image: Callable[[int], Optional[np.ndarray]]) -> ObjectObservation:
    """An object node for the cloud points `idx` inside the box (lo, hi): `unnamed_object` of a
    segment made of them (its colour, histogram and thumbnail from the views that saw most of them)."""
    pts = cloud.points[idx]
    _, first = np.unique(np.floor(pts / VOXEL_M).astype(np.int64), axis=0, return_index=True)
    frames, counts = np.unique(cloud.frame[idx], return_counts=True)
    order = frames[np.argsort(-counts)]
    seg = Segment(pts[first], lo, hi, frames, best_view=int(order[0]) if len(order) else -1,
                  good_views=tuple(int(k) for k in order[:GOOD_VIEWS]))
    seg.seen_views = len(frames)
    return unnamed_object(local_id, seg, cloud, colour_image)


def _desks(surfaces: Sequence[Element], cloud: RoomCloud,
           colour_image: Callable[[int], Optional[np.ndarray]]) -> list[tuple[Element, ObjectObservation]]:
    """The surfaces shaped like desks (`furniture.desk_shaped`), each with its desk node."""
    def as_object(local_id: str, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray) -> ObjectObservation:
        return points_object(local_id, lo, hi, idx, cloud, colour_image)

    out: list[tuple[Element, ObjectObservation]] = []
    for e in surfaces:
        if furniture.desk_shaped(e.height, furniture.surface_area(e), furniture.floor_seen_under(e, cloud)):
            for part in furniture.split_at_panels(e, cloud):
                out.append((e, furniture.desk_node(f"d{len(out)}", part, cloud, as_object)))
    return out


def _whole_named(named: list[ObjectObservation], cloud: RoomCloud, surfaces: Sequence[Element]) -> set[int]:
    """The named objects made whole (`whole_object_box`; in place): a detection of a kind solid
    to the floor with the floor seen under it leaves `named` (`furniture.open_below`), and a
    table-named object with a low solid top becomes a cabinet (`furniture.low_solid_top`).
    Returns the ids of the surfaces they own."""
    named[:] = [o for o in named if not furniture.open_below(o.label, *gravity_box(o, cloud), cloud)]
    tops = [whole_object_box(o, cloud, surfaces) for o in named]
    for k, (o, top) in enumerate(zip(named, tops)):
        if top is not None and furniture.low_solid_top(o, top, cloud):
            named[k] = furniture.renamed_by_shape(o, furniture.CABINET_LABEL)
            lo, hi = furniture.box_with_top(*gravity_box(o, cloud), top)
            named[k].size = vec3(hi - lo)
            named[k].box_centre = vec3(cloud.to_world((lo + hi) / 2))
    return {id(e) for e in tops if e is not None}


def hovering_seat(seg: Segment) -> bool:
    """A segment that hovers at seat height (its bottom between SEAT_MIN_BOTTOM_M and
    SEAT_MAX_BOTTOM_M): a chair's seat and back seen without its legs."""
    return furniture.SEAT_MIN_BOTTOM_M <= float(seg.lo[2]) <= SEAT_MAX_BOTTOM_M


def _couches(seats: Sequence[Element], segments: Sequence[Segment], cloud: RoomCloud,
             colour_image: Callable[[int], Optional[np.ndarray]],
             ) -> tuple[list[tuple[Element, tuple[np.ndarray, np.ndarray], ObjectObservation]], list[Segment]]:
    """The seat levels shaped like couches (`furniture.couch_shaped`), lowest first, each with its
    whole box and its couch node; and the segments that are no couch's part."""
    def as_object(local_id: str, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray) -> ObjectObservation:
        return points_object(local_id, lo, hi, idx, cloud, colour_image)

    out: list[tuple[Element, tuple[np.ndarray, np.ndarray], ObjectObservation]] = []
    left = list(segments)
    for e in sorted(seats, key=lambda e: e.height):
        if furniture.part_of_furniture(e, [box for _, box, _ in out]):
            continue                     # a second level of a couch already found
        parts = furniture.couch_parts(e, [(s.lo, s.hi) for s in left])
        if not furniture.couch_shaped(e.height, [furniture.back_or_arm_length(left[k].voxels, e.height) for k in parts]):
            continue
        lo, hi = furniture.couch_box(e, [(left[k].lo, left[k].hi) for k in parts])
        out.append((e, (lo, hi), furniture.couch_node(f"c{len(out)}", lo, hi, cloud, as_object)))
        left = [s for k, s in enumerate(left) if k not in set(parts)]
    return out, left


def top_object(local_id: str, el: Element, cloud: RoomCloud,
               colour_image: Callable[[int], Optional[np.ndarray]]) -> ObjectObservation:
    """Rule "a top without a floor": where the recording never saw the floor (a desk scanned from
    above), a horizontal surface no object owns is the top of furniture whose legs stand out of
    view, so an object node (the top's box, its points' colour), not the room's structure: what
    lies on it is ON it."""
    idx = np.flatnonzero(el.contains(cloud.points, SURFACE_SLAB_M))
    return points_object(local_id, el.lo, el.hi, idx, cloud, colour_image)


def structure_node(local_id: str, el: Element, cloud: RoomCloud) -> ObjectObservation:
    """A structure-layer node for a floor, wall or surface: its box, no colour evidence."""
    centre = cloud.to_world((el.lo + el.hi) / 2)
    size = np.maximum(el.hi - el.lo, 0.01)
    return ObjectObservation(
        local_id=local_id, labels=[el.label], scores=[1.0],
        mean=vec3(centre), var=vec3((size / 4) ** 2),
        # a uniform histogram: structure is matched across views by place and name, not colour
        n_points=max(1, el.n_points), size=vec3(size), hist=np.ones(HIST_SIZE),
        colour="grey", box_centre=vec3(centre), n_frames=max(1, el.frames),
        layer="structure")


def discover(named: list[ObjectObservation], cloud: RoomCloud, structure: Sequence[Element],
             colour_image: Callable[[int], Optional[np.ndarray]],
             ) -> tuple[list[ObjectObservation], list[ObjectObservation]]:
    """Give the named objects their whole boxes (in place; a table-named object with a low solid
    top becomes a cabinet, `furniture.low_solid_top`); return the objects found in depth (the
    desks named from their shape, then the unnamed objects) and the structure nodes (the floor,
    walls, and the surfaces no object owns: a level over a floor-standing object is its seat or
    top). Small named objects claim the points inside their boxes before segmentation; the
    whole boxes of floor-standing furniture name the segments inside them (a chair tucked under
    a table would be claimed by the table's box). A seat level with a couch's back or arm
    (`furniture.couch_shaped`) is a couch node that takes its parts; a worktop's box and the
    carrel panels beside it (`furniture.carrel_panel`) are its desks'; a low piece under a seat
    (`furniture.base_under_seat`) is that seat's base. None of these is a node of its own. A
    detection of a kind solid to the floor with the floor seen under it (`furniture.open_below`)
    is no object: it leaves `named` (in place), and its points are segmented like any others; a
    floor-standing detection of part of a kept face (`face_part`) leaves `named` too."""
    surfaces = [e for e in structure if e.footprint is not None]
    owned = _whole_named(named, cloud, surfaces)
    boxes = [gravity_box(o, cloud) for o in named]
    desks = _desks([e for e in surfaces if id(e) not in owned], cloud, colour_image)
    owned |= {id(e) for e, _ in desks}
    standing = [b for o, b in zip(named, boxes) if o.label in FLOOR_STANDING_LABELS]
    owned |= {id(e) for e in surfaces if id(e) not in owned and furniture.part_of_furniture(e, standing)}
    boxes += [gravity_box(d, cloud) for _, d in desks]
    # a worktop cut into desks is one piece of furniture: what lies inside its box (the carrels'
    # back panels under the tops) is part of it, and so are the panels standing beside it
    worktops = [furniture.desk_box(e) for e in {id(e): e for e, _ in desks}.values()]
    boxes += worktops
    claims = [b for o, b in zip(named, boxes) if o.label not in FLOOR_STANDING_LABELS]
    bounding = outside.bounding_walls(structure, cloud)
    inside = [s for s in room_candidates(cloud, structure, claims) if not outside.seen_through_wall(s, bounding, cloud)]
    segments = separate_resting(separate_shelf_contents(inside, surfaces, cloud), surfaces, cloud, colour_image)
    couches, segments = _couches([e for e in surfaces if id(e) not in owned], segments, cloud, colour_image)
    segments, found_walls = separate_at_walls(segments, cloud)
    couch_boxes = [box for _, box, _ in couches]
    owned |= {id(e) for e, _, _ in couches}
    owned |= {id(e) for e in surfaces if id(e) not in owned and furniture.part_of_furniture(e, couch_boxes)}
    boxes += couch_boxes
    seats = standing + couch_boxes + [(s.lo, s.hi) for s in segments if hovering_seat(s)]
    planes = [e for e in structure if e.plane is not None]
    screens = [b for o, b in zip(named, boxes) if colour_model.is_screen(o.label)]
    unnamed: list[ObjectObservation] = [desk for _, desk in desks] + [couch for _, _, couch in couches]
    pieces: list[tuple[Segment, ObjectObservation]] = []

    def part_of_another(seg: Segment, whole: bool = True) -> bool:
        return (named_by(seg, boxes) or own_edge(seg, claims) or cloud.floor_seen and floor_remnant(seg)
                or board_of_surface(seg, surfaces) or cloud.floor_seen and holds_up_top(seg, surfaces)
                or whole and not seg.on_board and (plane_remnant(seg, planes) or relief_of_found_wall(seg, found_walls))
                or furniture.base_under_seat(seg.lo, seg.hi, seats)
                or any(furniture.carrel_panel(seg.lo, seg.hi, *top) for top in worktops))

    # a segment that is part of something else stays so; a kept one in a row is cut at its
    # necks, and its parts are things, not a plane's relief (`row_parts`)
    for seg in segments:
        if part_of_another(seg):
            continue
        for part in row_parts(seg, cloud):
            if part is seg or not part_of_another(part, whole=False):
                pieces.append((part, unnamed_object("u", part, cloud, colour_image, screens)))
    pieces = rejoin_sheets(pieces, lambda seg: unnamed_object("u", seg, cloud, colour_image, screens))
    named[:] = [o for o in named if o.label not in FLOOR_STANDING_LABELS
                or not any(face_part(*gravity_box(o, cloud), seg) for seg, _ in pieces)]
    found = boxes + [(seg.lo, seg.hi) for seg, _ in pieces]
    pieces += [(seg, unnamed_object("u", seg, cloud, colour_image, screens))
               for seg in flat_things.flat_things(surfaces, cloud, colour_image, found)]
    for _, obj in pieces:
        unnamed.append(replace(obj, local_id=f"u{len(unnamed)}"))
    left = [e for e in structure if e.label != "front" and id(e) not in owned]
    if not cloud.floor_seen:
        unnamed += [top_object(f"t{k}", e, cloud, colour_image) for k, e in enumerate(left) if e.footprint is not None]
        left = [e for e in left if e.footprint is None]
    nodes = [structure_node(f"s{k}", e, cloud) for k, e in enumerate(left)]
    return unnamed, nodes
