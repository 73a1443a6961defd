"""Rule "seen through the wall" (`sg3d.ingest.discover.outside`): each threshold, on both sides."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from sg3d.ingest.discover.outside import bounding_walls, seen_through_wall
from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.segments import Segment
from sg3d.ingest.discover.structure import Element

# A room whose wall stands at a = 3 m (the room on a < 3), 4 m long (b -2..2) and 2.5 m high; the
# camera at the room's middle, 1.2 m up.
CAMERA = np.array([0.0, 0.0, 1.2])


def _view(at=CAMERA):
    pose = np.eye(4)
    pose[:3, 3] = at
    return SimpleNamespace(pose=pose)


def _wall() -> Element:
    return Element("wall", np.array([2.95, -2.0, 0.0]), np.array([3.05, 2.0, 2.5]), 1000, 3,
                   plane=(0.0, 3.0), side=-1.0)


def _room(extra=(), cameras=(CAMERA,)) -> RoomCloud:
    """The wall's face and the floor before it (9000-odd points), plus `extra` points, all seen
    from the first camera."""
    b, h = np.meshgrid(np.arange(-2.0, 2.001, 0.05), np.arange(0.0, 2.501, 0.05))
    face = np.stack([np.full(b.size, 3.0), b.ravel(), h.ravel()], axis=1)
    a, b = np.meshgrid(np.arange(0.0, 2.951, 0.05), np.arange(-2.0, 2.001, 0.05))
    floor = np.stack([a.ravel(), b.ravel(), np.zeros(a.size)], axis=1)
    pts = np.concatenate([face, floor, np.asarray(extra, float).reshape(-1, 3)])
    return RoomCloud(pts, np.zeros_like(pts), np.zeros(len(pts), np.int32), np.eye(3), 0.0,
                     [_view(c) for c in cameras])


def _points(n, a, b, h):
    return [(a, b, h)] * n


def _segment(voxels) -> Segment:
    v = np.asarray(voxels, float)
    return Segment(v, v.min(axis=0) - 0.0125, v.max(axis=0) + 0.0125, np.array([0]))


def test_a_wall_with_the_outside_seen_through_its_glass_bounds_the_room():
    # 300 points 1 m beyond, seen through the wall's face (its glass door): still a bounding wall
    cloud = _room(_points(300, 4.0, 0.0, 1.0))
    assert len(bounding_walls([_wall()], cloud)) == 1


def test_a_wall_bounds_the_room_with_at_most_a_thousandth_seen_past_it():      # WALL_SEEN_PAST
    # points 1 m beyond and 5 m along: the ray crosses the wall's plane past its end
    few = _room(_points(5, 4.0, 5.0, 1.0))          # 5 of ~9100: under a thousandth
    many = _room(_points(20, 4.0, 5.0, 1.0))        # 20: over
    assert len(bounding_walls([_wall()], few)) == 1
    assert bounding_walls([_wall()], many) == []


def test_what_lies_less_than_30_cm_beyond_counts_not_as_seen_past():          # WALL_FAR_M
    near = _room(_points(50, 3.25, 5.0, 1.0))
    far = _room(_points(50, 3.35, 5.0, 1.0))
    assert len(bounding_walls([_wall()], near)) == 1
    assert bounding_walls([_wall()], far) == []


def test_a_wall_with_a_camera_beyond_it_bounds_nothing():
    assert len(bounding_walls([_wall()], _room(cameras=(CAMERA, np.array([2.0, 0.0, 1.2]))))) == 1
    assert bounding_walls([_wall()], _room(cameras=(CAMERA, np.array([4.0, 0.0, 1.2])))) == []


def _outside_thing(a_near: float):
    """A 20 cm thing seen straight through the wall, its nearest voxels `a_near` beyond the camera."""
    b, h = np.meshgrid(np.arange(-0.1, 0.101, 0.025), np.arange(0.9, 1.101, 0.025))
    front = np.stack([np.full(b.size, a_near), b.ravel(), h.ravel()], axis=1)
    return _segment(np.concatenate([front, front + [0.2, 0.0, 0.0]]))


def test_a_thing_all_more_than_30_cm_beyond_a_bounding_wall_is_outside():      # WALL_FAR_M
    cloud = _room()
    walls = bounding_walls([_wall()], cloud)
    assert seen_through_wall(_outside_thing(3.35), walls, cloud)
    assert not seen_through_wall(_outside_thing(3.25), walls, cloud)   # its front 25 cm beyond: a recess
    assert not seen_through_wall(_outside_thing(3.35), [], cloud)     # no wall bounds the room


def test_a_thing_is_outside_when_half_of_it_was_seen_through_the_walls_face():   # SEEN_THROUGH_SHARE
    # voxels 50 cm beyond; the rays to those at b <= 2.0 cross the wall inside its face (b up to
    # ~1.9), those at b >= 2.5 past its end
    def thing(inside: int, past: int):
        bs = list(np.linspace(1.5, 2.0, inside)) + list(np.linspace(2.5, 2.8, past))
        return _segment([(3.5, b, 1.0) for b in bs])

    cloud = _room()
    walls = bounding_walls([_wall()], cloud)
    assert seen_through_wall(thing(6, 4), walls, cloud)
    assert not seen_through_wall(thing(4, 6), walls, cloud)
