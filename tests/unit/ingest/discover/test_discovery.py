"""Screens in view, left out of an object's surround: their boxes reach the border they were cut by."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from sg3d.ingest.discover.discovery import discover, screens_in_view
from sg3d.ingest.discover.room_cloud import RoomCloud


def _camera_at_origin():
    K = np.array([[500.0, 0, 320], [0, 500.0, 240], [0, 0, 1]])
    return SimpleNamespace(pose=np.eye(4), K=K, size=(640, 480))


def test_a_screen_box_that_stops_just_short_of_the_border_runs_to_it():
    view = _camera_at_origin()
    cloud = RoomCloud(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, int), np.eye(3), 0.0, [view])
    # 2 m ahead: x from 0.2 to 1.16 m projects to u 370..610 (the image ends at 640)
    near_border = (np.array([0.2, -0.3, 2.0]), np.array([1.16, 0.1, 2.05]))
    inside = (np.array([-0.6, -0.3, 2.0]), np.array([-0.2, 0.1, 2.05]))
    (a, b) = screens_in_view([near_border, inside], cloud, view)
    assert a[2] == 640 and 360 <= a[0] <= 380
    assert 160 <= b[0] <= 175 and 265 <= b[2] <= 275      # well inside: kept as measured


# --------------------------------------------------------------------------- each threshold, on both sides

def _surface(x_hi: float = 1.0, height: float = 0.75, label: str = "surface"):
    """A horizontal surface at `height` over [0, x_hi] x [0, 1] (footprint cells of 5 cm)."""
    from sg3d.ingest.discover.structure import Element

    cells = (int(round(x_hi / 0.05)), 20)
    return Element(label, np.array([0.0, 0.0, height - 0.03]), np.array([x_hi, 1.0, height]), 100, 3,
                   height, np.ones(cells, bool), np.array([0.0, 0.0]))


def _segment(voxels, frames=(0,)):
    from sg3d.ingest.discover.segments import Segment

    v = np.asarray(voxels, float)
    return Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array(frames, int))


TABLE_LO, TABLE_HI = np.array([0.0, 0.0, 0.0]), np.array([1.0, 1.0, 0.75])


def test_a_table_owns_a_surface_covering_half_its_footprint():       # OWN_FOOTPRINT_SHARE
    from sg3d.ingest.discover.discovery import owned_surface

    assert owned_surface(TABLE_LO, TABLE_HI, [_surface(0.55)]) is not None
    assert owned_surface(TABLE_LO, TABLE_HI, [_surface(0.45)]) is None


def test_a_table_owns_a_surface_within_15_cm_of_its_box():           # TOP_TOLERANCE_M
    from sg3d.ingest.discover.discovery import owned_surface

    assert owned_surface(TABLE_LO, TABLE_HI, [_surface(height=0.75 + 0.14)]) is not None
    assert owned_surface(TABLE_LO, TABLE_HI, [_surface(height=0.75 + 0.16)]) is None


def _voxels_in_box(inside: int, n: int = 100):
    """n voxels on a line, `inside` of them within the unit box, the rest beyond x = 1."""
    xs = [0.5] * inside + [1.5] * (n - inside)
    return _segment([(x, 0.5, 0.5 + 0.001 * k) for k, x in enumerate(xs)])


def test_a_segment_is_a_named_objects_with_half_its_voxels_in_its_box():   # NAMED_SHARE
    from sg3d.ingest.discover.discovery import named_by

    unit = (np.zeros(3), np.ones(3))
    assert named_by(_voxels_in_box(55), [unit])
    assert not named_by(_voxels_in_box(45), [unit])


def test_a_named_objects_box_is_grown_by_2_cm():                      # NAMED_MARGIN_M
    from sg3d.ingest.discover.discovery import named_by

    unit = (np.zeros(3), np.ones(3))
    assert named_by(_segment([(1.019, 0.5, 0.5 + 0.01 * k) for k in range(10)]), [unit])
    assert not named_by(_segment([(1.021, 0.5, 0.5 + 0.01 * k) for k in range(10)]), [unit])


def _wall_x1():
    from sg3d.ingest.discover.structure import Element

    return Element("front", np.zeros(3), np.ones(3), 1000, 3, plane=(0.0, 1.0))   # the plane x = 1


def _relief(offsets):
    """Voxels at the given offsets from the plane x = 1."""
    return _segment([(1.0 + off, 0.1 * k, 0.5) for k, off in enumerate(offsets)])


def test_a_relief_within_7_cm_of_a_plane_is_part_of_it():              # REMNANT_DISTANCE_M
    from sg3d.ingest.discover.discovery import plane_remnant

    assert plane_remnant(_relief([0.065] * 10), [_wall_x1()])
    assert not plane_remnant(_relief([0.075] * 10), [_wall_x1()])


def test_a_relief_up_to_12_cm_thick_is_part_of_the_plane():            # REMNANT_THICKNESS_M
    from sg3d.ingest.discover.discovery import plane_remnant

    assert plane_remnant(_relief([-0.055, 0.055] * 5), [_wall_x1()])
    assert not plane_remnant(_relief([-0.065, 0.065] * 5), [_wall_x1()])


def _flat_piece(top: float, thickness: float):
    from sg3d.ingest.discover.segments import Segment

    return Segment(np.zeros((12, 3)), np.array([0.0, 0.0, top - thickness]), np.array([0.5, 0.5, top]), np.array([0]))


def test_a_piece_on_the_floor_up_to_10_cm_high_is_floor():             # FLOOR_REMNANT_TOP_M
    from sg3d.ingest.discover.discovery import floor_remnant

    assert floor_remnant(_flat_piece(0.095, 0.05))
    assert not floor_remnant(_flat_piece(0.105, 0.05))


def test_a_piece_on_the_floor_up_to_6_cm_thick_is_floor():             # FLOOR_REMNANT_THICKNESS_M
    from sg3d.ingest.discover.discovery import floor_remnant

    assert floor_remnant(_flat_piece(0.08, 0.055))
    assert not floor_remnant(_flat_piece(0.08, 0.065))


def test_a_segment_rests_on_a_surface_within_5_cm_of_its_level():      # RESTING_M
    from sg3d.ingest.discover.discovery import resting_on
    from sg3d.ingest.discover.segments import Segment

    def at(bottom):
        return Segment(np.zeros((12, 3)), np.array([0.4, 0.4, bottom]), np.array([0.6, 0.6, bottom + 0.1]), np.array([0]))
    assert resting_on(at(0.75 + 0.045), [_surface()])
    assert not resting_on(at(0.75 + 0.055), [_surface()])


@pytest.mark.parametrize("size,word", [
    ((1.0, 0.5, 0.24), "flat"), ((1.0, 0.5, 0.26), None),              # FLAT_RATIO
    ((0.3, 0.2, 0.61), "tall"), ((0.3, 0.2, 0.59), None),              # TALL_RATIO
    ((0.4, 0.3, 0.74), "box-shaped"), ((0.4, 0.3, 0.76), None),        # BOX_RATIO
])
def test_shape_words(size, word):
    from sg3d.ingest.discover.discovery import shape_word

    assert shape_word(size) == word


def test_an_unnamed_object_has_a_1_cm_position_spread_at_least_and_32_surface_points():
    # VOXEL_VAR_FLOOR, SURFACE_SAMPLE: 100 voxels on a horizontal plane
    from sg3d.ingest.discover.discovery import unnamed_object

    grid = [(0.025 * i, 0.025 * j, 0.8) for i in range(10) for j in range(10)]
    cloud = RoomCloud(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, int), np.eye(3), 0.0, [])
    obs = unnamed_object("u0", _segment(grid, frames=()), cloud, lambda index: None)
    assert obs.var[2] == pytest.approx(0.01 ** 2)
    assert len(obs.surface) == 32 * 3


def test_a_screen_box_6_percent_from_the_border_is_kept_as_measured():   # SCREEN_BORDER_SHARE
    view = _camera_at_origin()
    cloud = RoomCloud(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, int), np.eye(3), 0.0, [view])
    # 2 m ahead: x up to 1.12 m projects to u = 600, 40 px (6 %) from the border
    (box,) = screens_in_view([(np.array([0.2, -0.3, 2.0]), np.array([1.12, 0.1, 2.05]))], cloud, view)
    assert 598 <= box[2] <= 602


def test_a_voxel_marks_a_disc_of_12_5_mm_radius():                    # VOXEL_DISC_M
    from sg3d.ingest.discover.discovery import segment_reading

    image = np.full((480, 640, 3), 120, np.uint8)
    one = segment_reading((np.array([320.0]), np.array([240.0]), np.array([1.0])), _camera_at_origin(), image,
                          (300, 220, 340, 260))
    assert one.n == 113            # 1 m away at f = 500 px: a disc of radius 6 px


# --- one sheet in pieces (`one_sheet`: a curtain's folds) ------------------------------------------

def _sheet(a0: float, width: float = 0.15, depth: float = 0.1, h0: float = 0.1, h1: float = 1.5):
    from sg3d.ingest.discover.segments import Segment

    g = np.arange(0.0125, 3, 0.025)
    v = np.array([(a0 + x, y, z) for x in g[g < width] for y in g[g < depth] for z in h0 + g[g < h1 - h0]])
    return Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array([0]))


@pytest.mark.parametrize("gap,one", [(0.08, True), (0.12, False)])
def test_two_tall_pieces_within_10_cm_are_one_sheet(gap, one):          # REJOIN_GAP_M
    from sg3d.ingest.discover.discovery import one_sheet

    assert one_sheet(_sheet(0.0), _sheet(0.15 + gap), "white", "white") is one


def test_pieces_of_two_colours_or_not_tall_are_two_things():
    from sg3d.ingest.discover.discovery import one_sheet

    assert not one_sheet(_sheet(0.0), _sheet(0.2), "white", "red")
    assert not one_sheet(_sheet(0.0, h1=0.3), _sheet(0.2, h1=0.3), "white", "white")


@pytest.mark.parametrize("h0,one", [(1.0, True), (1.2, False)])
def test_one_sheets_pieces_share_half_the_shorter_ones_height(h0, one):  # REJOIN_HEIGHT_SHARE
    from sg3d.ingest.discover.discovery import one_sheet

    # the second piece runs from h0 to 1.9 m (0.9 or 0.7 m tall, tall either way); the first up to
    # 1.5 m: they share 0.5 m (over half of 0.9) or 0.3 m (under half of 0.7)
    assert one_sheet(_sheet(0.0), _sheet(0.2, width=0.1, h0=h0, h1=1.9), "white", "white") is one


@pytest.mark.parametrize("depth,one", [(0.175, True), (0.225, False)])
def test_one_sheet_lies_on_one_vertical_plane(depth, one):               # REJOIN_MAX_THICKNESS_M
    from sg3d.ingest.discover.discovery import one_sheet, plane_thickness

    a, b = _sheet(0.0, width=0.4, depth=depth, h1=1.9), _sheet(0.45, width=0.4, depth=depth, h1=1.9)
    assert (plane_thickness(np.concatenate([a.voxels, b.voxels])) <= 0.2) is one
    assert one_sheet(a, b, "white", "white") is one


def test_rejoined_pieces_are_one_node():
    from sg3d.ingest.discover.discovery import rejoin_sheets

    made = []

    def remake(seg):
        made.append(seg)
        return SimpleNamespace(colour="white")

    pieces = [(_sheet(0.0), SimpleNamespace(colour="white")), (_sheet(2.0), SimpleNamespace(colour="white")),
              (_sheet(0.2), SimpleNamespace(colour="white"))]
    out = rejoin_sheets(pieces, remake)
    assert len(out) == 2 and len(made) == 1
    assert len(made[0].voxels) == len(pieces[0][0].voxels) + len(pieces[2][0].voxels)


# --- relief of a wall found in a welded segment (`relief_of_found_wall`) ----------------------------

def _found_wall():
    """A wall found on the plane b = 0 (normal along b), the room on its b > 0 side, seen from a = 0
    to 1.4 m and up to 2 m."""
    from sg3d.ingest.discover.structure import Element

    return Element("wall", np.array([0.0, -0.05, 0.0]), np.array([1.4, 0.05, 2.0]), 100, 5,
                   plane=(np.pi / 2, 0.0), side=1.0)


def _board(b: float, thickness: float = 0.05, a0: float = 0.2):
    from sg3d.ingest.discover.segments import Segment

    g = np.arange(0.0, 0.7, 0.025)
    v = np.array([(a0 + x, b + y, 1.6 + z) for x in g[g < 0.7] for y in g[g < thickness] for z in g[g < 0.3]])
    return Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array([0]))


@pytest.mark.parametrize("b,relief", [(-0.12, True), (-0.15, False)])
def test_what_lies_up_to_13_cm_behind_a_found_wall_is_the_wall(b, relief):   # FOUND_WALL_DISTANCE_M
    from sg3d.ingest.discover.discovery import relief_of_found_wall

    assert relief_of_found_wall(_board(b, thickness=0.025), [_found_wall()]) is relief


@pytest.mark.parametrize("b,relief", [(0.06, True), (0.09, False)])
def test_what_stands_before_a_found_wall_is_its_relief_within_7_cm(b, relief):   # REMNANT_DISTANCE_M
    from sg3d.ingest.discover.discovery import relief_of_found_wall

    assert relief_of_found_wall(_board(b, thickness=0.025), [_found_wall()]) is relief


def test_a_found_wall_claims_reliefs_only_near_the_piece_seen():                # REJOIN_GAP_M
    from sg3d.ingest.discover.discovery import relief_of_found_wall

    assert relief_of_found_wall(_board(0.0, a0=1.45), [_found_wall()])
    assert not relief_of_found_wall(_board(0.0, a0=1.55), [_found_wall()])


# --- a row of things (`row_parts`) ------------------------------------------------------------------

def _row(length: float):
    """Two 0.3 m blocks standing side by side, joined by a one-voxel neck, `length` long in all."""
    g = 0.025
    xs = np.arange(0.0, length, g) + g / 2
    v = [(x, y, z) for x in xs for y in np.arange(0.0, 0.2, g) + g / 2 for z in np.arange(0.8, 1.0, g)
         if x < 0.3 or x > length - 0.3 or abs(y - 0.1125) < 0.02]
    return _segment(v)


@pytest.mark.parametrize("length,cut", [(1.25, True), (1.15, False)])
def test_only_a_segment_longer_than_one_thing_is_cut_as_a_row(monkeypatch, length, cut):   # WELD_MIN_EXTENT_M
    from sg3d.ingest.discover import discovery

    monkeypatch.setattr(discovery, "depth_evidence", lambda seg, cloud: None)
    monkeypatch.setattr(discovery, "exists", lambda seg: True)
    seg = _row(length)
    parts = discovery.row_parts(seg, None)
    assert (len(parts) == 2) is cut
    if not cut:
        assert parts == [seg]


def test_a_rows_parts_that_fail_depth_are_dropped(monkeypatch):
    from sg3d.ingest.discover import discovery

    monkeypatch.setattr(discovery, "depth_evidence", lambda seg, cloud: None)
    monkeypatch.setattr(discovery, "exists", lambda seg: float(seg.lo[0]) < 0.5)
    parts = discovery.row_parts(_row(1.3), None)
    assert len(parts) == 1 and float(parts[0].lo[0]) < 0.5


def _face(foot: float, depth: float, length: float = 1.6, top: float = 0.6):
    """A bed's side seen from low: a face `length` long along a, `depth` deep in b, from `foot` to
    `top`, with a one-voxel neck halfway along it (a seam)."""
    g = 0.025
    bs = np.arange(round(depth / g)) * g + g / 2
    xs = np.arange(round(length / g)) * g + g / 2
    v = [(x, y, z) for x in xs for y in bs for z in np.arange(foot, top, g) + g / 2
         if abs(x - length / 2) > 0.05 or abs(y - bs[len(bs) // 2]) < 0.01]
    return _segment(v)


# --- a detection of part of a face (`face_part`) ----------------------------------------------------

def _bed_side(depth: float = 0.1):
    """A bed's side seen from low: a face 1.6 m long along a, `depth` deep, from 4 cm (the floor's
    slab cut away) to 0.6 m."""
    return _face(0.04, depth)


def _named_box(a0: float, width: float, depth: float = 0.08, top: float = 0.5, b0: float = 0.01):
    return np.array([a0, b0, 0.0]), np.array([a0 + width, b0 + depth, top])


@pytest.mark.parametrize("margin,part", [(0.0475, True), (0.0525, False)])
def test_a_named_box_lies_in_the_face_grown_by_5_cm(margin, part):          # FACE_PART_MARGIN_M
    from sg3d.ingest.discover.discovery import face_part

    seg = _bed_side()
    lo, hi = _named_box(0.4, 0.5)
    lo[2] = float(seg.lo[2]) - margin
    assert face_part(lo, hi, seg) is part


@pytest.mark.parametrize("width,part", [(0.79, True), (0.81, False)])
def test_the_face_is_twice_as_long_as_the_named_box(width, part):           # FACE_PART_RATIO
    from sg3d.ingest.discover.discovery import face_part

    seg = _bed_side()
    assert float(seg.size[0]) == pytest.approx(1.6)
    assert face_part(*_named_box(0.4, width), seg) is part


@pytest.mark.parametrize("depth,part", [(0.2, True), (0.25, False)])
def test_a_face_that_claims_a_named_box_lies_on_one_sheets_plane(depth, part):   # REJOIN_MAX_THICKNESS_M
    from sg3d.ingest.discover.discovery import face_part

    assert face_part(*_named_box(0.4, 0.5, depth=0.08), _bed_side(depth)) is part


def test_a_chair_standing_before_a_face_is_deeper_than_its_slab():
    from sg3d.ingest.discover.discovery import face_part

    assert not face_part(*_named_box(0.4, 0.45, depth=0.45), _bed_side())


# --- a named object's own edge (`own_edge`) ----------------------------------------------------------

SCREEN_LO, SCREEN_HI = np.array([0.0, 0.0, 1.2]), np.array([0.8, 0.1, 1.6])   # 0.8 wide, 0.4 tall


def _rim(width: float):
    """A bezel seen beyond the screen's box: a strip down its right side, from a = 0.8 (the box's
    edge) to 0.8 + `width` (the real tv's rim, kitchen, ran 0.23 m beyond its box)."""
    g = 0.025
    return _segment([(x, 0.05, z) for x in np.arange(0.8, 0.8 + width - 1e-9, g) for z in np.arange(1.25, 1.6, g)])


@pytest.mark.parametrize("width,edge", [(0.35, True), (0.5, False)])
def test_a_piece_within_a_quarter_of_a_named_box_beyond_it_is_its_edge(width, edge):   # EDGE_GROWTH
    from sg3d.ingest.discover.discovery import own_edge

    # a quarter of the 0.8 m width: the box may stop 20 cm short of the screen's edge, so half the
    # strip's voxels lie within a = 1.0 when it is 0.35 m wide (9 of 14), not when 0.5 m (9 of 20)
    assert own_edge(_rim(width), [(SCREEN_LO, SCREEN_HI)]) is edge


def test_a_things_beside_a_small_named_box_is_not_its_edge():
    from sg3d.ingest.discover.discovery import own_edge

    cup = (np.array([0.0, 0.0, 0.9]), np.array([0.06, 0.1, 1.0]))
    beside = _segment([(x, y, z) for x in np.arange(0.07, 0.15, 0.025) for y in (0.02, 0.06)
                       for z in np.arange(0.9, 1.0, 0.025)])
    assert not own_edge(beside, [cup])


@pytest.mark.parametrize("bottom,edge", [(1.54, True), (1.56, False)])
def test_what_stands_on_a_named_box_is_not_its_edge(bottom, edge):           # RESTING_M
    from sg3d.ingest.discover.discovery import own_edge

    piece = _segment([(x, 0.05, z) for x in np.arange(0.3, 0.5, 0.025) for z in np.arange(bottom, 1.64, 0.02)])
    piece.lo[2] = bottom
    assert own_edge(piece, [(SCREEN_LO, SCREEN_HI)]) is edge


# --- a board's own thickness (`board_of_surface`) ----------------------------------------------------

def _under_board(top: float, thickness: float = 0.12, width: float = 0.6):
    from sg3d.ingest.discover.segments import Segment

    return Segment(np.zeros((12, 3)), np.array([0.2, 0.2, top - thickness]), np.array([0.2 + width, 0.5, top]),
                   np.array([0]))


@pytest.mark.parametrize("top,board", [(0.71, True), (0.69, False)])
def test_a_flat_piece_topped_within_5_cm_of_a_surface_is_its_board(top, board):   # RESTING_M
    from sg3d.ingest.discover.discovery import board_of_surface

    assert board_of_surface(_under_board(top), [_surface(height=0.75)]) is board


@pytest.mark.parametrize("thickness,board", [(0.15, True), (0.16, False)])
def test_only_a_flat_piece_is_a_surfaces_board(thickness, board):             # FLAT_RATIO
    from sg3d.ingest.discover.discovery import board_of_surface

    # flat: at most a quarter of its 0.6 m side tall
    assert board_of_surface(_under_board(0.75, thickness), [_surface(height=0.75)]) is board


def test_a_flat_piece_beside_a_surface_is_not_its_board():
    from sg3d.ingest.discover.discovery import board_of_surface

    piece = _under_board(0.75)
    piece.lo[0], piece.hi[0] = 1.3, 1.9                      # the surface ends at a = 1.0
    assert not board_of_surface(piece, [_surface(height=0.75)])


def test_where_the_floor_was_not_seen_a_free_surface_is_an_object_and_the_floor_keeps_no_node():
    """A desk scan: the top no object owns is an object node (flat, the top's size); with the floor
    seen the same level is the room's structure."""
    from sg3d.core.model import UNNAMED_LABEL
    from sg3d.ingest.discover.structure import horizontal_surfaces

    a, b = np.meshgrid(np.arange(0.0, 1.2, 0.01), np.arange(0.0, 0.6, 0.01))
    top = np.stack([a.ravel(), b.ravel(), np.zeros(a.size)], axis=1)
    pose = np.eye(4)
    pose[:3, 3] = (0.6, 0.3, 0.5)
    view = SimpleNamespace(pose=pose, K=np.array([[100.0, 0, 80], [0, 100.0, 60], [0, 0, 1]]), depth=np.zeros((120, 160)),
                           index=0)
    p = np.vstack([top] * 3)
    cloud = RoomCloud(p, np.tile([0.0, 0.0, 1.0], (len(p), 1)), np.repeat(np.arange(3), len(top)), np.eye(3), 0.0,
                      [view] * 3, False)
    structure = horizontal_surfaces(cloud)
    unnamed, nodes = discover([], cloud, structure, lambda k: None)
    assert nodes == []
    [desk] = unnamed
    assert desk.label == UNNAMED_LABEL and desk.layer == "object" and desk.shape == "flat"
    # the surface rule's closing takes 2 cells (10 cm) off every side
    assert desk.size[0] == pytest.approx(1.0, abs=0.06) and desk.size[1] == pytest.approx(0.4, abs=0.06)


def _leg(a: float, foot: float, top: float, columns: int = 2, b: float = 0.5):
    """A leg of `columns` voxel columns from a (2.5 cm apart) at b, from `foot` to `top` (the
    segment's box adds half a voxel to the voxel centres)."""
    h = np.arange(foot + 0.0125, top - 0.0125 + 1e-9, 0.025)
    return _segment([[a + 0.025 * k, b, z] for k in range(columns) for z in h])


def test_a_leg_stands_on_the_floor_10_cm_at_most():                   # LEG_FOOT_M
    from sg3d.ingest.discover.discovery import holds_up_top

    assert holds_up_top(_leg(0.5, 0.0875, 0.70), [_surface()])
    assert not holds_up_top(_leg(0.5, 0.1125, 0.70), [_surface()])


def test_a_leg_reaches_within_8_cm_of_the_top_and_not_past_it():      # LEG_REACH_M
    from sg3d.ingest.discover.discovery import holds_up_top

    assert holds_up_top(_leg(0.5, 0.0, 0.675), [_surface()])            # 7.5 cm below its level
    assert not holds_up_top(_leg(0.5, 0.0, 0.65), [_surface()])         # 10 cm: a box under the table
    assert not holds_up_top(_leg(0.5, 0.0, 0.80), [_surface()])         # past the top: a chair's back


def test_half_a_leg_lies_under_the_top():                              # LEG_UNDER_SHARE
    from sg3d.ingest.discover.discovery import holds_up_top

    # the top's footprint ends at a = 1 m: two of three columns under it, then one
    assert holds_up_top(_leg(0.9625, 0.0, 0.70, columns=3), [_surface()])
    assert not holds_up_top(_leg(0.9875, 0.0, 0.70, columns=3), [_surface()])
