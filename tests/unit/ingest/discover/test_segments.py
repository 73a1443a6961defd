"""Class-agnostic segments (`sg3d.ingest.discover.segments`) on hand-made voxels, clouds and views."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.segments import (
    Segment,
    depth_evidence,
    exists,
    object_points,
    outside_boxes,
    outside_room,
    plausible_size,
    split_at_colour_edge,
    split_at_necks,
    voxel_sample,
    voxel_segments,
)
from sg3d.ingest.discover.structure import Element
from sg3d.ingest.objects.existence import View

K = np.array([[500.0, 0, 320], [0, 500.0, 240], [0, 0, 1]])


def _cloud(points, frames, n_views: int = 2, views=None) -> RoomCloud:
    p = np.asarray(points, float).reshape(-1, 3)
    return RoomCloud(p, np.zeros_like(p), np.asarray(frames, int), np.eye(3), 0.0,
                     views if views is not None else [None] * n_views)


def _cells(cells, h: float = 0.5) -> Segment:
    """A one-layer segment of voxels at the given (i, j) cells of 2.5 cm."""
    v = np.array([(0.0125 + 0.025 * i, 0.0125 + 0.025 * j, h) for i, j in cells])
    return Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array([0]))


def test_a_segments_voxel_sample_depends_on_its_voxels_only():
    rng = np.random.default_rng(3)
    voxels = rng.uniform(0, 1, (500, 3))
    first = voxel_sample(voxels)
    rng.uniform(0, 1, 1000)          # whatever else was drawn in between
    assert len(first) == 200 and np.array_equal(first, voxel_sample(voxels.copy()))
    assert not np.array_equal(first, voxel_sample(voxels[1:]))
    assert np.array_equal(voxel_sample(voxels[:10]), voxels[:10])


def test_a_segments_voxel_sample_does_not_change_with_the_last_bit_of_its_coordinates():
    # another CPU's BLAS kernel or thread split moves a voxel centre by an ulp: the same sample
    voxels = np.random.default_rng(4).uniform(0, 2, (500, 3))
    assert np.array_equal(voxel_sample(np.nextafter(voxels, 9.0)), np.nextafter(voxel_sample(voxels), 9.0))
    assert not np.array_equal(voxel_sample(voxels), voxel_sample(voxels + 0.001))

# --------------------------------------------------------------------------- each threshold, on both sides

def test_an_object_is_5_cm_to_2_5_m_large():                          # MIN_EXTENT_M, MAX_EXTENT_M
    assert plausible_size(np.array([0.055, 0.01, 0.01])) and not plausible_size(np.array([0.045, 0.01, 0.01]))
    assert plausible_size(np.array([2.45, 0.5, 0.5])) and not plausible_size(np.array([2.55, 0.5, 0.5]))


def _judged(seen: int, looked: int, hits: int = 10, free: int = 0) -> bool:
    seg = Segment(np.zeros((12, 3)), np.zeros(3), np.ones(3), np.array([0]), hits, free, seen, looked)
    return exists(seg)


def test_a_segment_exists_when_5_views_saw_it():                       # MIN_SEEN_VIEWS
    assert _judged(5, 5) and not _judged(4, 5)


def test_a_segment_exists_when_a_quarter_of_the_views_that_could_tell_saw_it():   # MIN_SEEN_SHARE
    assert _judged(11, 40) and not _judged(9, 40)


def test_a_segment_exists_when_half_its_voxels_are_solid():            # MIN_HIT_RATIO
    assert _judged(5, 5, hits=11, free=9) and not _judged(5, 5, hits=9, free=11)


def test_a_named_objects_box_claims_points_within_1_cm_of_it():        # CLAIM_MARGIN_M
    unit = [(np.zeros(3), np.ones(3))]
    assert list(outside_boxes(np.array([[1.009, 0.5, 0.5], [1.011, 0.5, 0.5]]), unit)) == [False, True]


def test_object_points_leave_out_the_floor_slab_and_the_ceiling():     # FLOOR_SLAB_M, MAX_HEIGHT_M
    cloud = _cloud([(0.5, 0.5, h) for h in (0.035, 0.045, 2.55, 2.65)], [0] * 4)
    assert list(object_points(cloud, [])) == [False, True, True, False]


def test_object_points_leave_out_3_cm_of_a_wall_and_of_a_surface():    # PLANE_CUT_M, SURFACE_SLAB_M
    wall = Element("wall", np.zeros(3), np.ones(3), 1000, 3, plane=(0.0, 2.0))          # the plane x = 2
    top = Element("surface", np.array([0.0, 0.0, 0.72]), np.array([1.0, 1.0, 0.75]), 100, 3, 0.75,
                  np.ones((20, 20), bool), np.array([0.0, 0.0]))
    cloud = _cloud([(1.975, 0.5, 1.0), (1.965, 0.5, 1.0), (0.5, 0.5, 0.775), (0.5, 0.5, 0.785)], [0] * 4)
    assert list(object_points(cloud, [wall, top])) == [False, True, False, True]


def _line(n: int, frames=(0, 1)):
    """n voxels of 2.5 cm in a row, each seen by `frames`, and a point at the origin (one frame)."""
    pts = [(0.0, 0.0, 0.0)] + [(0.0125 + 0.025 * k, 0.0125, 0.0125) for k in range(n) for _ in frames]
    fr = [0] + [f for _ in range(n) for f in frames]
    return _cloud(pts, fr)


def _segments(cloud):
    return voxel_segments(cloud, np.ones(len(cloud.points), bool))


def test_a_segment_has_12_voxels_at_least():                           # MIN_VOXELS
    assert len(_segments(_line(12))) == 1
    assert _segments(_line(11)) == []


def test_a_voxel_counts_when_two_frames_saw_it():                      # MIN_VOXEL_FRAMES
    assert len(_segments(_line(20, frames=(0, 1)))) == 1
    assert _segments(_line(20, frames=(0,))) == []


def test_voxels_are_2_5_cm():                                           # VOXEL_M
    (seg,) = _segments(_line(20))
    assert seg.size[0] == pytest.approx(0.5)


def _grid_segment():
    """10 x 10 voxels 2 cm apart, 2 m in front of the origin (gravity frame = world)."""
    v = np.array([(-0.09 + 0.02 * i, -0.09 + 0.02 * j, 2.0) for i in range(10) for j in range(10)])
    return Segment(v, v.min(axis=0), v.max(axis=0), np.array([0]))


def _looking(depth_m: float, x: float = 0.0) -> View:
    pose = np.eye(4)
    pose[0, 3] = x
    return View(0, K, pose, (640, 480), np.full((120, 160), depth_m, np.float32))


def _evidence(*views) -> Segment:
    seg = _grid_segment()
    depth_evidence(seg, _cloud(np.zeros((0, 3)), [], views=list(views)))
    return seg


def test_a_voxel_2_m_away_is_hit_within_8_cm():                       # HIT_TOLERANCE_M, HIT_TOLERANCE_REL
    assert _evidence(_looking(2.075)).hits == 100
    assert _evidence(_looking(2.085)).hits == 0


def test_a_segments_colour_is_read_in_its_3_best_views():              # GOOD_VIEWS
    assert _evidence(*[_looking(2.0)] * 4).good_views == (0, 1, 2)


def test_a_good_view_shows_three_quarters_of_the_segment():            # GOOD_VIEW_INSIDE
    # the camera moved left: the image's right border at x = 1.28 m - 1.22 (8 of 10 columns) or - 1.24 (7)
    assert _evidence(_looking(2.0, x=-1.22)).good_views == (0,)
    assert _evidence(_looking(2.0, x=-1.24)).good_views == ()


def _two_blobs(blob, neck):
    a = [(i, j) for i in range(blob[0]) for j in range(blob[1])]
    gap = len(neck[0])
    b = [(i + blob[0] + gap, j) for i, j in a]
    joint = [(blob[0] + i, j) for i in range(gap) for j in neck[1]]
    return _cells(a + joint + b)


def test_things_touching_at_a_neck_one_voxel_wide_come_apart():        # NECK_CELLS
    assert len(split_at_necks(_two_blobs((7, 7), ((0, 1), (3,))))) == 2
    assert len(split_at_necks(_two_blobs((7, 7), ((0, 1), (2, 3, 4))))) == 1


def test_a_thing_on_a_table_is_a_core_of_6_cells_once_eroded():         # CORE_CELLS
    assert len(split_at_necks(_two_blobs((4, 5), ((0,), (2,))))) == 2      # cores of 2 x 3
    assert len(split_at_necks(_two_blobs((4, 4), ((0,), (2,))))) == 1      # cores of 2 x 2


# --- touching, not one colour (`split_at_colour_edge`) ------------------------------------------------

def _box_and_patch(patch_cells, patch_chroma, box_chroma=(0.0, 2.0)):
    """A white box 8 x 6 cells, two voxels tall, with a patch of `patch_cells` (i, j) cells (its
    own colour, `patch_chroma` a*, b*) welded to its side with no neck: voxels and chroma."""
    box = [(i, j) for i in range(8) for j in range(6)]
    cells = box + list(patch_cells)
    v = np.array([(0.0125 + 0.025 * i, 0.0125 + 0.025 * j, h) for i, j in cells for h in (0.5, 0.525)])
    seg = Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array([0]))
    chroma = np.array([box_chroma] * (2 * len(box)) + [patch_chroma] * (2 * len(patch_cells)), float)
    return seg, chroma


PATCH = [(i, j) for i in range(8, 11) for j in range(4)]        # 3 x 4 cells against the box's side


def test_a_red_thing_against_a_white_box_comes_apart_at_its_colour_edge():      # COLOUR_EDGE_DELTA
    parts = split_at_colour_edge(*_box_and_patch(PATCH, (45.0, 30.0)))
    assert sorted(len(p.voxels) for p in parts) == [24, 96]


def test_two_colours_25_apart_are_two_things():                                 # COLOUR_EDGE_DELTA
    assert len(split_at_colour_edge(*_box_and_patch(PATCH, (27.0, 2.0)))) == 2
    assert len(split_at_colour_edge(*_box_and_patch(PATCH, (23.0, 2.0)))) == 1


def test_a_colour_patch_is_a_thing_from_6_cells():                              # CORE_CELLS
    assert len(split_at_colour_edge(*_box_and_patch([(8, j) for j in range(6)], (45.0, 30.0)))) == 2
    assert len(split_at_colour_edge(*_box_and_patch([(8, j) for j in range(5)], (45.0, 30.0)))) == 1


def test_a_segment_no_view_read_stays_whole():
    seg, chroma = _box_and_patch(PATCH, (45.0, 30.0))
    assert split_at_colour_edge(seg, np.full_like(chroma, np.nan)) == [seg]


def test_one_colour_with_noise_stays_whole():
    seg, chroma = _box_and_patch(PATCH, (0.0, 2.0))
    chroma += np.random.default_rng(1).normal(0, 4, chroma.shape)
    assert split_at_colour_edge(seg, chroma) == [seg]


def _beyond(x: float, far_behind: float = 0.005) -> bool:
    wall = Element("wall", np.zeros(3), np.ones(3), 1000, 3, plane=(0.0, 2.0), side=-1.0, far_behind=far_behind)
    seg = Segment(np.zeros((12, 3)), np.array([x - 0.05, 0.0, 0.5]), np.array([x + 0.05, 0.1, 0.6]), np.array([0]))
    return outside_room(seg, [wall])


def test_a_segment_30_cm_behind_a_sure_wall_is_outside_the_room():     # WALL_FAR_M
    assert not _beyond(2.29) and _beyond(2.31)


def test_a_wall_is_sure_when_1_percent_of_the_points_lie_far_behind_it():   # WALL_SURE_FAR
    assert _beyond(2.5, far_behind=0.009) and not _beyond(2.5, far_behind=0.011)


# --- welded along a wall (`split_at_wall`) ---------------------------------------------------------

def _wall_and_box(width: float = 1.4, height: float = 1.2, box: float = 0.4, plane_rows: int = 1):
    """A board/wall piece on the plane b = 0 (`width` along a, `height` tall, `plane_rows` voxels
    deep) welded to a solid box standing in front of it (b from 0.1 to 0.1 + box)."""
    from sg3d.ingest.discover.segments import VOXEL_M

    g = np.arange(0.0125, 10, VOXEL_M)
    a, h = g[g < width], g[g < height]
    wall = np.array([(x, -0.0125 - VOXEL_M * r, z) for x in a for z in h for r in range(plane_rows)])
    s = g[g < box]
    # the box touches the wall through a bridge of voxels 2.5 cm apart (one 26-neighbourhood)
    front = np.array([(x, 0.0125 + y, z) for x in s for y in np.concatenate([[0.0], s + VOXEL_M]) for z in s])
    v = np.concatenate([wall, front])
    return Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array([0]))


def test_a_big_segment_with_a_wall_in_it_is_cut_there():
    from sg3d.ingest.discover.segments import split_at_wall

    parts = split_at_wall(_wall_and_box())
    assert len(parts) == 2
    wall, box = parts
    assert float(np.ptp(wall.voxels[:, 1])) <= 0.12 and float(box.lo[1]) > 0.05


@pytest.mark.parametrize("width,cut", [(1.25, True), (1.10, False)])
def test_only_a_segment_wider_than_an_object_is_cut_at_a_wall(width, cut):     # WELD_MIN_EXTENT_M
    from sg3d.ingest.discover.segments import split_at_wall

    assert (len(split_at_wall(_wall_and_box(width=width, height=1.0))) > 1) is cut


@pytest.mark.parametrize("height,cut", [(0.65, True), (0.55, False)])
def test_the_wall_cut_away_spans_60_cm_in_height(height, cut):                 # WELD_PLANE_MIN_SPAN_M
    from sg3d.ingest.discover.segments import split_at_wall

    assert (len(split_at_wall(_wall_and_box(width=1.4, height=height, box=0.3))) > 1) is cut


@pytest.mark.parametrize("box,cut", [(0.40, True), (0.70, False)])
def test_the_wall_holds_30_percent_of_the_segment(box, cut):                   # WELD_PLANE_SHARE
    from sg3d.ingest.discover.segments import strongest_vertical_plane, split_at_wall

    seg = _wall_and_box(width=1.3, height=0.7, box=box)
    share = float(strongest_vertical_plane(seg.voxels)[2].mean())
    assert (share >= 0.3) is cut
    assert (len(split_at_wall(seg)) > 1) is cut


@pytest.mark.parametrize("rows,one", [(4, True), (6, False)])
def test_a_board_scattered_6_cm_by_depth_noise_stays_one_piece(rows, one):      # WELD_PLANE_SLAB_M
    """Voxels within 6 cm of the plane are its own; a thicker layer leaves a relief part (within 12 cm,
    it goes with the plane) or, farther, a part of its own."""
    from sg3d.ingest.discover.segments import strongest_vertical_plane

    seg = _wall_and_box(width=1.4, height=1.0, box=0.3, plane_rows=rows)
    on = strongest_vertical_plane(seg.voxels)[2]
    wall = seg.voxels[:, 1] < 0
    assert bool(on[wall].all()) is one

