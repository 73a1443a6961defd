"""Windows from physics (`sg3d.ingest.discover.windows`): each rule's thresholds on both sides, and
whole faces seen by hand-made views of a wall at a = 2 m with a hole, a door or an occluder."""
from __future__ import annotations

from typing import Optional

import numpy as np
import pytest

from sg3d.ingest.discover import windows as W
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import Element
from sg3d.ingest.objects.existence import View

EPS = 1e-3


def test_a_ray_sees_the_wall_within_the_slab_and_through_it_past_the_far_margin():
    plane = np.full(7, 2.0)
    depth = np.array([2.0 + W.PLANE_SLAB_M - EPS, 2.0 - W.PLANE_SLAB_M + EPS, 2.0 - W.PLANE_SLAB_M - EPS,
                      2.0 + W.PLANE_SLAB_M + EPS, 2.0 + W.THROUGH_M - EPS, 2.0 + W.THROUGH_M + EPS, 0.0])
    assert W.ray_verdict(depth, plane).tolist() == [W.WALL, W.WALL, W.UNKNOWN, W.UNKNOWN, W.UNKNOWN,
                                                   W.THROUGH, W.THROUGH]


def test_a_cell_is_open_when_enough_views_saw_through_it_and_more_than_saw_the_wall():
    n = W.MIN_THROUGH_VIEWS
    through = np.array([n, n - 1, n, n + 1])
    wall = np.array([0, 0, n, n])
    assert W.open_cell(through, wall).tolist() == [True, False, False, True]


def test_a_window_is_big_enough_both_ways():
    m = W.MIN_WINDOW_M
    assert W.window_sized(m, m)
    assert not W.window_sized(m - EPS, 1.0)
    assert not W.window_sized(1.0, m - EPS)


def test_a_hole_reaching_down_to_the_floor_is_no_window():
    assert W.above_floor(W.MIN_SILL_M)
    assert not W.above_floor(W.MIN_SILL_M - EPS)


def test_a_window_is_bounded_by_the_walls_face_on_both_sides_and_below():
    solid = np.ones((20, 20), bool)
    solid[5:15, 5:15] = False
    rows, cols = slice(5, 15), slice(5, 15)
    assert W.in_the_wall(solid, rows, cols)
    need = int(np.ceil(W.BOUND_SHARE * 10))
    for side in (np.s_[3:5, 5:5 + 10 - need + 1], np.s_[15:17, 5:5 + 10 - need + 1], np.s_[5:15, 3:5]):
        short = solid.copy()
        short[side] = False
        assert not W.in_the_wall(short, rows, cols), side
    enough = solid.copy()
    enough[3:5, 5:5 + 10 - need] = False
    assert W.in_the_wall(enough, rows, cols)
    assert not W.in_the_wall(solid, slice(0, 10), cols)          # no wall seen under it: the face's edge


def test_a_no_return_counts_only_inside_an_area_of_no_return():
    through = np.zeros((9, 9), bool)
    through[1:8, 1:8] = True
    through[0, 4] = True
    kept = W.hole_pixels(through)
    assert kept[2:7, 2:7].all() and not kept[1, 1] and not kept[0, 4]
    lone = np.zeros((5, 5), bool)
    lone[2, 2] = True
    assert not W.hole_pixels(lone).any()


def test_a_rectangle_is_mostly_open_among_its_decided_cells():
    opened = np.zeros((10, 10), bool)
    opened[:7] = True
    wall = ~opened
    assert W.rectangle_fill(opened, wall) == pytest.approx(0.7)
    wall[:, 5:] = False                     # cells no view decided do not count
    assert W.rectangle_fill(opened, wall) == pytest.approx(70 / 85)
    assert W.rectangle_fill(np.zeros((2, 2), bool), np.zeros((2, 2), bool)) == 0.0


# --- whole faces: a wall at a = 2 m (normal along a), cameras at a = 0 looking along +a ---

SMALL = (60, 80)
SIZE = (320, 240)
K = np.array([[262.5, 0.0, 159.5], [0.0, 262.5, 119.5], [0.0, 0.0, 1.0]])


def _view(b: float, h: float, depth_at) -> View:
    """A camera at (0, b, h) looking along +a; `depth_at(b, h)` -> what its rays return at the
    plane a = 2 (the plane's depth, 0 for no return, or another depth)."""
    R = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = R, (0.0, b, h)
    v, u = np.mgrid[0:SMALL[0], 0:SMALL[1]]
    x = ((u + 0.5) * 4 - 0.5 - K[0, 2]) / K[0, 0]
    y = ((v + 0.5) * 4 - 0.5 - K[1, 2]) / K[1, 1]
    hit_b, hit_h = b - 2.0 * x, h - 2.0 * y
    depth = np.vectorize(depth_at)(hit_b, hit_h).astype(np.float32)
    return View(0, K, pose, SIZE, depth)


def _faces(depth_at) -> list[Element]:
    views = [_view(b, h, depth_at) for b in (-0.6, 0.0, 0.6) for h in (0.9, 1.3)]
    cloud = RoomCloud(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, np.int32), np.eye(3), 0.0, views)
    wall = Element("wall", np.array([2.0, -2.0, 0.0]), np.array([2.0, 2.0, 2.4]), 1000, 6, plane=(0.0, 2.0), side=-1.0)
    face = W.face_votes(W.view_rays(cloud), wall)
    assert face is not None
    return W.face_windows(face)


def _hole(b0: float, b1: float, h0: float, h1: float, inside: Optional[float] = 0.0):
    return lambda b, h: inside if b0 <= b <= b1 and h0 <= h <= h1 else 2.0


def test_a_hole_in_the_wall_seen_through_is_a_window_of_its_size():
    found = _faces(_hole(-0.5, 0.5, 0.9, 1.8))
    assert len(found) == 1
    w = found[0]
    assert w.label == "window"
    assert abs((w.hi[1] - w.lo[1]) - 1.0) <= 0.1 and abs(w.lo[2] - 0.9) <= 0.1 and abs(w.hi[2] - 1.8) <= 0.1
    assert abs(w.lo[0] - 2.0) < 0.01


def test_the_outside_seen_far_beyond_the_hole_is_seen_through_too():
    assert len(_faces(_hole(-0.5, 0.5, 0.9, 1.8, inside=6.0))) == 1


def test_a_hole_down_to_the_floor_is_a_door_not_a_window():
    assert _faces(_hole(-0.45, 0.45, -1.0, 2.0)) == []


def test_something_in_front_of_the_wall_is_unknown_not_a_window():
    assert _faces(_hole(-0.5, 0.5, 0.9, 1.8, inside=1.5)) == []


def test_a_recess_less_deep_than_the_through_margin_is_no_window():
    assert _faces(_hole(-0.5, 0.5, 0.9, 1.8, inside=2.0 + W.THROUGH_M - 0.05)) == []


def test_a_hole_smaller_than_a_window_is_none():
    assert _faces(_hole(-0.15, 0.15, 1.0, 1.6)) == []


def _wall_points(length: float, top: float) -> tuple[np.ndarray, np.ndarray]:
    """Points on the plane a = 1.5 from b = -length/2, 1 cm apart, from the floor to `top`."""
    b, h = np.meshgrid(np.arange(-length / 2, length / 2, 0.01), np.arange(0.0, top + 0.005, 0.01))
    pts = np.stack([np.full(b.size, 1.5), b.ravel(), h.ravel()], axis=1)
    return pts, np.tile([-1.0, 0.0, 0.0], (len(pts), 1))


def test_a_windows_wall_runs_a_metre_and_reaches_up_past_a_sill():
    from sg3d.ingest.discover.structure import WALL_MIN_LENGTH
    from tests.unit.ingest.discover.clouds import room_of

    top = W.WINDOW_WALL_MIN_TOP_M
    found = W.wall_planes(room_of(_wall_points(2.0, top + 0.02)))
    assert len(found) == 1 and abs(found[0].plane[1] - 1.5) < 0.02 and found[0].side == -1.0
    assert W.wall_planes(room_of(_wall_points(2.0, top - 0.05))) == []           # a furniture front
    assert W.wall_planes(room_of(_wall_points(WALL_MIN_LENGTH - 0.05, 2.0))) == []
    assert len(W.wall_planes(room_of(_wall_points(WALL_MIN_LENGTH + 0.05, 2.0)))) == 1


def test_a_rectangle_below_the_least_fill_is_no_window():
    """A wall with a 1 m square hole seen through; an L of open cells (a corner of it the wall's)."""
    face = np.zeros((3,) + (40, 40), np.int32)
    face[W.WALL] = 5
    face[W.THROUGH, 10:30, 10:30] = 5
    face[W.WALL, 10:30, 10:30] = 0
    wall = Element("wall", np.array([2.0, -1.0, 0.0]), np.array([2.0, 1.0, 2.0]), 1000, 6, plane=(0.0, 2.0), side=-1.0)
    assert len(W.face_windows(W.Face(wall, -1.0, face))) == 1
    for corner, kept in ((10, True), (12, False)):      # an L of open cells: 300 / 400 and 256 / 400 open
        notched = face.copy()
        notched[W.THROUGH, 10:10 + corner, 10:10 + corner] = 0
        notched[W.WALL, 10:10 + corner, 10:10 + corner] = 5
        assert (len(W.face_windows(W.Face(wall, -1.0, notched))) == 1) is kept, corner
    assert 1 - 100 / 400 >= W.MIN_FILL > 1 - 144 / 400
