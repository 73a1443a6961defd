"""The room's structure (`sg3d.ingest.discover.structure`) on hand-made clouds: floor, surfaces, walls, fronts."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import floor_element, horizontal_surfaces, plane_fill, surface_name, walls
from tests.unit.ingest.discover.clouds import room_of


def _plane(start, direction, length: float, height: float, normal) -> tuple[np.ndarray, np.ndarray]:
    """Points on a vertical rectangle from `start` (a, b) along `direction`, 1 cm apart."""
    t, h = np.meshgrid(np.arange(0.0, length, 0.01), np.arange(0.05, 0.05 + height, 0.01))
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    pts = np.stack([start[0] + t.ravel() * d[0], start[1] + t.ravel() * d[1], h.ravel()], axis=1)
    return pts, np.tile(np.asarray(normal, float), (len(pts), 1))


def _room(*planes) -> RoomCloud:
    """A floor seen from a camera at the origin, and the given vertical planes."""
    return room_of(*planes)


def test_a_wall_keeps_its_length_where_a_stronger_wall_took_its_end():
    """Two walls meet at a shallow angle (a parapet behind a glass door, a wall beside a bay):
    the stronger one takes the points of the other's first 30 cm, and the weaker still counts
    its whole 1.1 m; a 0.5 m face is no wall."""
    main = _plane((1.5, -1.0), (0.0, 1.0), 1.05, 1.2, (-1.0, 0.0, 0.0))
    angle = np.radians(10)
    side = _plane((1.5, 0.0), (-np.sin(angle), np.cos(angle)), 1.1, 0.8, (-np.cos(angle), -np.sin(angle), 0.0))
    found = walls(_room(main, side))
    assert [e.label for e in found] == ["wall", "wall"]
    assert abs(np.degrees(found[1].plane[0]) - 10) < 2.5
    short = _plane((1.5, 0.0), (0.0, 1.0), 0.5, 0.8, (-1.0, 0.0, 0.0))
    assert walls(_room(short)) == []


def test_a_front_is_a_face_and_the_folds_of_a_curtain_are_not():
    along, height = np.meshgrid(np.arange(0.0, 1.5, 0.01), np.arange(0.0, 1.2, 0.01))
    assert plane_fill(along.ravel(), height.ravel()) > 0.9
    strips = (np.floor(along / 0.05) % 9) == 0        # a fold touches the plane every 45 cm
    assert plane_fill(along[strips], height[strips]) < 0.45


# --------------------------------------------------------------------------- each threshold, on both sides

X_WALL = (-1.0, 0.0, 0.0)       # the normal of a wall across x, facing the camera at the origin


def _labels(cloud) -> list[str]:
    return [e.label for e in walls(cloud)]


def test_a_wall_is_1_m_long():                                         # WALL_MIN_LENGTH
    # its 2-98 percentile extent: 96 % of 1.06 m and of 1.03 m
    assert _labels(_room(_plane((1.5, -0.6), (0, 1), 1.06, 1.0, X_WALL))) == ["wall"]
    assert _labels(_room(_plane((1.5, -0.6), (0, 1), 1.03, 1.0, X_WALL))) == []


def test_a_wall_is_60_cm_tall():                                       # WALL_MIN_HEIGHT
    assert _labels(_room(_plane((1.5, -0.6), (0, 1), 1.5, 0.65, X_WALL))) == ["wall"]
    assert _labels(_room(_plane((1.5, -0.6), (0, 1), 1.5, 0.60, X_WALL))) == []


def test_a_wall_point_has_a_normal_within_0_15_of_horizontal():        # WALL_NORMAL_COS
    def tilted(z):
        n = np.array([-1.0, 0.0, z])
        return _room(_plane((1.5, -0.6), (0, 1), 1.2, 1.0, tuple(n / np.linalg.norm(n))))
    assert _labels(tilted(0.14)) == ["wall"]
    assert _labels(tilted(0.16)) == []


def test_a_walls_angle_is_read_to_its_2_degree_bin():                  # WALL_ANGLE_BIN_DEG
    (wall,) = walls(_room(_plane((1.5, -0.6), (0, 1), 1.2, 1.0, X_WALL)))
    assert np.degrees(wall.plane[0]) == pytest.approx(1.0)            # the centre of the bin 0-2 degrees


def test_parallel_planes_12_cm_apart_are_two():                        # WALL_OFFSET_BIN_M
    # the strongest plane clears +-3 offset bins (9 cm) of the vote around it
    cloud = _room(_plane((1.3, -0.6), (0, 1), 1.2, 1.0, X_WALL), _plane((1.42, -0.6), (0, 1), 1.2, 1.0, X_WALL))
    assert sorted(_labels(cloud)) == ["front", "wall"]


def _behind(n: int, depth: float):
    """`n` points `depth` behind the wall x = 1.5 (flat things seen through a doorway)."""
    k = np.arange(n)
    pts = np.stack([np.full(n, 1.5 + depth), -0.5 + (k % 100) * 0.01, 0.3 + (k // 100) * 0.01], axis=1)
    return pts, np.tile([0.0, 0.0, 1.0], (n, 1))


def test_a_wall_has_a_tenth_of_the_rooms_points_behind_it_at_most():   # WALL_MAX_BEHIND
    wall = _plane((1.5, -0.6), (0, 1), 1.2, 1.0, X_WALL)            # 12000 points, the floor 12500
    assert _labels(_room(wall, _behind(2500, 0.2))) == ["wall"]     # 9.3 % behind
    assert _labels(_room(wall, _behind(3000, 0.2))) == ["front"]    # 10.9 %


def test_a_point_is_behind_a_wall_beyond_its_5_cm_slab():              # WALL_SLAB_M
    wall = _plane((1.5, -0.6), (0, 1), 1.2, 1.0, X_WALL)
    assert _labels(_room(wall, _behind(4000, 0.045))) == ["wall"]
    assert _labels(_room(wall, _behind(4000, 0.055))) == ["front"]


def test_at_most_10_walls():                                            # MAX_WALLS
    planes = []
    for k in range(11):                     # 11 planes 2 m from the origin, 16 degrees apart
        th = np.radians(16 * k)
        start = (2.0 * np.cos(th) + 0.6 * np.sin(th), 2.0 * np.sin(th) - 0.6 * np.cos(th))
        planes.append(_plane(start, (-np.sin(th), np.cos(th)), 1.2, 0.8, (-np.cos(th), -np.sin(th), 0.0)))
    assert len(walls(_room(*planes))) == 10


def _lines(step_cm: int):
    """A front (most of the floor lies behind it) that is vertical lines `step_cm` apart."""
    t, h = np.meshgrid(np.arange(0, 121, step_cm) * 0.01, np.arange(0.05, 1.05, 0.01))
    pts = np.stack([np.full(t.size, 1.0), -0.6 + t.ravel(), h.ravel()], axis=1)
    return pts, np.tile(X_WALL, (len(pts), 1))


def test_a_front_fills_45_percent_of_its_cells():                       # FRONT_MIN_FILL
    assert _labels(_room(_lines(12))) == ["front"]                      # fills 46 %
    assert _labels(_room(_lines(13))) == []                             # 42 %


def test_fill_is_counted_in_5_cm_cells():                               # FILL_CELL_M
    along, height = np.meshgrid(np.arange(0.0, 1.5, 0.1), np.arange(0.0, 1.2, 0.01))   # lines 10 cm apart
    assert plane_fill(along.ravel(), height.ravel()) == pytest.approx(0.54, abs=0.03)


def _floor(h: float, up_z: float = 1.0, n: int = 300):
    k = np.arange(n)
    p = np.stack([(k % 20) * 0.05, (k // 20) * 0.05, np.full(n, h)], axis=1)
    nz = np.tile([np.sqrt(1 - up_z ** 2), 0.0, up_z], (n, 1))
    return RoomCloud(p, nz, np.zeros(n, int), np.eye(3), 0.0, [SimpleNamespace(pose=np.eye(4))])


def test_the_floor_is_its_points_within_4_cm_facing_up():              # FLOOR_SLAB_M, UP_NORMAL_COS
    assert floor_element(_floor(0.035)).n_points == 300
    assert floor_element(_floor(0.045)) is None
    assert floor_element(_floor(0.0, up_z=0.96)) is not None
    assert floor_element(_floor(0.0, up_z=0.94)) is None


def _top(side_x: float, side_y: float, h: float, frames: int = 4) -> RoomCloud:
    """A horizontal top seen by `frames` frames, 1 cm apart."""
    a, b = np.meshgrid(np.arange(0, side_x, 0.01), np.arange(0, side_y, 0.01))
    p = np.stack([a.ravel(), b.ravel(), np.full(a.size, h)], axis=1)
    pts = np.vstack([p] * frames)
    return RoomCloud(pts, np.tile([0.0, 0.0, 1.0], (len(pts), 1)), np.repeat(np.arange(frames), len(p)),
                     np.eye(3), 0.0, [None] * frames)


def test_a_surface_lies_25_cm_above_the_floor_at_least():               # SURFACE_MIN_HEIGHT
    assert len(horizontal_surfaces(_top(1.0, 1.0, 0.27))) == 1
    assert horizontal_surfaces(_top(1.0, 1.0, 0.23)) == []


def test_a_surface_is_seen_by_3_frames():                               # SURFACE_MIN_FRAMES
    assert len(horizontal_surfaces(_top(1.0, 1.0, 0.5, frames=3))) == 1
    assert horizontal_surfaces(_top(1.0, 1.0, 0.5, frames=2)) == []


def test_a_surface_covers_a_tenth_of_a_square_metre():                  # SURFACE_MIN_AREA, SURFACE_CELL_M
    # the closing of its 5 cm cells takes 2 cells off every side: 10 x 11 cells keep 6 x 7 (0.105 m^2)
    (top,) = horizontal_surfaces(_top(0.5, 0.55, 0.5))
    assert top.hi[0] - top.lo[0] == pytest.approx(0.30) and top.hi[1] - top.lo[1] == pytest.approx(0.35)
    assert horizontal_surfaces(_top(0.5, 0.5, 0.5)) == []               # 6 x 6 cells: 0.09 m^2


def test_a_surfaces_level_holds_300_points():                           # SURFACE_PEAK_MIN_POINTS
    def sparse(extra: int) -> RoomCloud:
        """One point in every other 5 cm cell, seen by 3 frames (270 points), and `extra` from a 4th."""
        pts = [(0.05 * i + 0.025, 0.05 * j + 0.025, 0.5) for i in range(0, 18, 2) for j in range(0, 20, 2)]
        p = np.array(pts * 3 + pts[:extra])
        f = np.array([0] * 90 + [1] * 90 + [2] * 90 + [3] * extra)
        return RoomCloud(p, np.tile([0.0, 0.0, 1.0], (len(p), 1)), f, np.eye(3), 0.0, [None] * 4)
    assert len(horizontal_surfaces(sparse(40))) == 1                     # 310 points
    assert horizontal_surfaces(sparse(20)) == []                         # 290


@pytest.mark.parametrize("height,depth,name", [
    (0.76, 0.6, "counter"), (0.74, 0.6, "surface"), (1.09, 0.6, "counter"), (1.12, 0.6, "shelf"),   # COUNTER_HEIGHT, SHELF_MIN_HEIGHT
    (0.9, 0.42, "counter"), (0.9, 0.38, "shelf"),                       # COUNTER_MIN_DEPTH
    (0.5, 0.44, "shelf"), (0.5, 0.46, "surface"),                       # SHELF_MAX_DEPTH
])
def test_surface_names(height, depth, name):
    assert surface_name(height, np.zeros(3), np.array([2.0, depth, height])) == name


def test_a_rough_wall_gathers_its_votes_in_3_cm_offset_bins():          # WALL_OFFSET_BIN_M
    def rough(n_side: int):
        """n_side^2 points of a wall, each up to 4 cm before or behind the plane x = 1.5."""
        i, j = np.meshgrid(np.arange(n_side), np.arange(n_side))
        off = (((i * 7 + j * 3) % 10) / 9.0 - 0.5) * 0.08
        pts = np.stack([1.5 + off.ravel(), -0.6 + i.ravel() * 1.2 / n_side, 0.05 + j.ravel() / n_side], axis=1)
        return pts, np.tile(X_WALL, (len(pts), 1))
    assert _labels(_room(rough(26))) == ["wall"]         # 676 points: 3 bins x 3 cm hold 500 votes
    assert _labels(_room(rough(20))) == []               # 400 points


# --------------------------------------------------------------------------- a recording that never saw the floor

def _top_scan(floor_seen: bool) -> RoomCloud:
    """A desk top 1.2 x 0.6 m seen from above, 3 frames, its level the lowest point (h = 0)."""
    a, b = np.meshgrid(np.arange(0.0, 1.2, 0.01), np.arange(0.0, 0.6, 0.01))
    top = np.stack([a.ravel(), b.ravel(), np.zeros(a.size)], axis=1)
    p = np.vstack([top] * 3)
    frames = np.repeat(np.arange(3), len(top))
    views = [SimpleNamespace(pose=np.eye(4))] * 3
    return RoomCloud(p, np.tile([0.0, 0.0, 1.0], (len(p), 1)), frames, np.eye(3), 0.0, views, floor_seen)


def test_where_the_floor_was_not_seen_the_lowest_level_is_a_surface_not_the_floor():
    seen, unseen = _top_scan(True), _top_scan(False)
    assert floor_element(seen) is not None and horizontal_surfaces(seen) == []     # below SURFACE_MIN_HEIGHT
    assert floor_element(unseen) is None
    [top] = horizontal_surfaces(unseen)
    assert top.label == "surface" and top.height == pytest.approx(0.0, abs=0.01)
    assert top.hi[0] - top.lo[0] == pytest.approx(1.0, abs=0.06)     # less the closing's 2 cells a side
