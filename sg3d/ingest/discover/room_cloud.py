"""The room as one point cloud: the depth of every detected frame, fused in the gravity frame.

Class-agnostic discovery and the room's structure work on what the depth camera saw, named or
not. The detected frames' small depth images (`existence.View`, 1/4 resolution) are lifted to
world points (Eq. 8 on a coarse grid), turned into the gravity frame (e1, e2, up of
`sg3d.core.geometry.horizontal_basis`) and kept with their surface normals and the frame that saw them.
Coordinates in this module are gravity-frame: (a, b, h) with h = p . up - floor height.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional, Sequence

import numpy as np

from sg3d.core.geometry import horizontal_frame

if TYPE_CHECKING:
    from sg3d.ingest.objects.existence import View

# Farther than this, Kinect-type depth is too noisy to outline an object.
MAX_RANGE_M = 4.0
# A neighbour across a depth jump gives no normal (relative to depth, plus an absolute floor).
NORMAL_JUMP_REL = 0.05
NORMAL_JUMP_M = 0.02


@dataclass
class RoomCloud:
    """Points seen by the detected frames, gravity frame (metres above the floor for h)."""

    points: np.ndarray        # N x 3 (a, b, h)
    normals: np.ndarray       # N x 3 unit, gravity frame; 0 where no normal could be computed
    frame: np.ndarray         # N frame indices (position in `views`)
    basis: np.ndarray         # 3 x 3 rows e1, e2, up (world -> gravity frame)
    floor: float              # p . up of the floor plane
    views: Sequence           # the existence.View of every frame, same order
    floor_seen: bool = True   # False: `floor` is the lowest point seen, and the floor was never in view

    @property
    def world_to_camera(self) -> list[np.ndarray]:
        if not hasattr(self, "_w2c"):
            self._w2c = [np.linalg.inv(v.pose) for v in self.views]
        return self._w2c

    def to_world(self, local: np.ndarray) -> np.ndarray:
        """Gravity-frame coordinates (h above the floor) -> world points."""
        q = np.array(local, dtype=np.float64, copy=True)
        q[..., 2] += self.floor
        return q @ self.basis


def camera_grid(view: View) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 8 on a view's small depth grid: camera-frame points (H x W x 3) and the depth (H x W)."""
    d = view.depth.astype(np.float64)
    h, w = d.shape
    fx = view.size[0] / w
    fy = view.size[1] / h
    K = view.K
    v, u = np.mgrid[0:h, 0:w]
    uu = (u + 0.5) * fx - 0.5
    vv = (v + 0.5) * fy - 0.5
    return np.stack([(uu - K[0, 2]) / K[0, 0] * d, (vv - K[1, 2]) / K[1, 1] * d, d], axis=-1), d


def grid_points(view: View, basis: np.ndarray, floor: float) -> tuple[np.ndarray, np.ndarray]:
    """A view's small depth grid as gravity-frame points (H x W x 3, h above `floor`; garbage
    where the depth is 0) and its depth (H x W)."""
    cam, d = camera_grid(view)
    return to_gravity(cam, view, basis, floor), d


def to_gravity(cam: np.ndarray, view: View, basis: np.ndarray, floor: float) -> np.ndarray:
    """Camera-frame points of a view -> gravity-frame points (h above `floor`)."""
    R, t = view.pose[:3, :3], view.pose[:3, 3]
    local = (cam @ R.T + t) @ basis.T
    local[..., 2] -= floor
    return local


def view_points(view: View, basis: np.ndarray, floor: float) -> tuple[np.ndarray, np.ndarray]:
    """Eq. 8 on a view's small depth grid: gravity-frame points and unit normals (zero where a
    neighbour lies across a depth jump or has no depth)."""
    cam, d = camera_grid(view)
    R = view.pose[:3, :3]
    local = to_gravity(cam, view, basis, floor)
    normals = np.zeros_like(local)
    dx = cam[1:-1, 2:] - cam[1:-1, :-2]
    dy = cam[2:, 1:-1] - cam[:-2, 1:-1]
    n = np.cross(dx, dy)
    centre = d[1:-1, 1:-1]
    ok = centre > 0
    for nb in (d[1:-1, 2:], d[1:-1, :-2], d[2:, 1:-1], d[:-2, 1:-1]):
        ok &= (nb > 0) & (np.abs(nb - centre) < NORMAL_JUMP_REL * centre + NORMAL_JUMP_M)
    norm = np.linalg.norm(n, axis=-1)
    ok &= norm > 0
    # a surface faces the camera that sees it: the normal points back along the ray
    n = n * np.where(np.sum(n * cam[1:-1, 1:-1], axis=-1) > 0, -1.0, 1.0)[..., None]
    inner = np.zeros_like(n)
    inner[ok] = (n[ok] / norm[ok][:, None]) @ R.T @ basis.T
    normals[1:-1, 1:-1] = inner
    valid = (d > 0) & (d < MAX_RANGE_M)
    return local[valid], normals[valid]


def room_cloud(views: Sequence, up: Sequence[float], floor: Optional[float]) -> RoomCloud:
    """Fuse the views' depth into one gravity-frame cloud. Without a floor (the recording never
    saw it), the lowest percentile of heights stands in for it as the origin of h only."""
    basis = horizontal_frame(up)
    base = 0.0 if floor is None else float(floor)
    pts, nrm, idx = [], [], []
    for k, view in enumerate(views):
        p, n = view_points(view, basis, base)
        pts.append(p)
        nrm.append(n)
        idx.append(np.full(len(p), k, dtype=np.int32))
    points = np.concatenate(pts) if pts else np.zeros((0, 3))
    normals = np.concatenate(nrm) if nrm else np.zeros((0, 3))
    frame = np.concatenate(idx) if idx else np.zeros(0, np.int32)
    if floor is None and len(points):
        shift = float(np.percentile(points[:, 2], 1.0))
        points[:, 2] -= shift
        base += shift
    return RoomCloud(points, normals, frame, basis, base, list(views), floor is not None)
