"""The room's structure and its segments on hand-made clouds: walls, fronts, voxel samples."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import plane_fill, walls


def _plane(start, direction, length: float, height: float, normal) -> tuple[np.ndarray, np.ndarray]:
    """Points on a vertical rectangle from `start` (a, b) along `direction`, 1 cm apart."""
    t, h = np.meshgrid(np.arange(0.0, length, 0.01), np.arange(0.05, 0.05 + height, 0.01))
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    pts = np.stack([start[0] + t.ravel() * d[0], start[1] + t.ravel() * d[1], h.ravel()], axis=1)
    return pts, np.tile(np.asarray(normal, float), (len(pts), 1))


def _room(*planes) -> RoomCloud:
    """A floor seen from a camera at the origin, and the given vertical planes."""
    a, b = np.meshgrid(np.arange(-1.0, 1.5, 0.02), np.arange(-1.0, 1.0, 0.02))
    points = [np.stack([a.ravel(), b.ravel(), np.zeros(a.size)], axis=1)]
    normals = [np.tile([0.0, 0.0, 1.0], (a.size, 1))]
    for pts, nrm in planes:
        points.append(pts)
        normals.append(nrm)
    p = np.vstack(points)
    return RoomCloud(p, np.vstack(normals), np.zeros(len(p), int), np.eye(3), 0.0, [SimpleNamespace(pose=np.eye(4))])


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


def test_a_segments_voxel_sample_depends_on_its_voxels_only():
    from sg3d.ingest.discover.segments import SAMPLE_VOXELS, voxel_sample

    rng = np.random.default_rng(3)
    voxels = rng.uniform(0, 1, (500, 3))
    first = voxel_sample(voxels)
    rng.uniform(0, 1, 1000)          # whatever else was drawn in between
    assert len(first) == SAMPLE_VOXELS and np.array_equal(first, voxel_sample(voxels.copy()))
    assert not np.array_equal(first, voxel_sample(voxels[1:]))
    assert np.array_equal(voxel_sample(voxels[:10]), voxels[:10])
