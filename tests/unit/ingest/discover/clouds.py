"""Hand-made room clouds for the structure tests."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from sg3d.ingest.discover.room_cloud import RoomCloud


def room_of(*planes, floor_step: float = 0.02) -> RoomCloud:
    """A floor (points `floor_step` apart over [-1, 1.5] x [-1, 1]) seen from a camera at the
    origin, and the given (points, normals) of each plane."""
    a, b = np.meshgrid(np.arange(-1.0, 1.5, floor_step), np.arange(-1.0, 1.0, floor_step))
    points = [np.stack([a.ravel(), b.ravel(), np.zeros(a.size)], axis=1)]
    normals = [np.tile([0.0, 0.0, 1.0], (a.size, 1))]
    for pts, nrm in planes:
        points.append(pts)
        normals.append(nrm)
    p = np.vstack(points)
    return RoomCloud(p, np.vstack(normals), np.zeros(len(p), int), np.eye(3), 0.0, [SimpleNamespace(pose=np.eye(4))])
