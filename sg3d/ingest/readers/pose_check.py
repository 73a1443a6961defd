"""The check every camera pose passes before its frame is used, whatever layout it came from."""
from __future__ import annotations

from typing import Optional

import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.core.model import WORLD_EXTENT_M

ROTATION_TOLERANCE = 1e-3    # |R^T R - I| entries of a rigid rotation
BOTTOM_ROW_TOLERANCE = 1e-6  # |last row - (0, 0, 0, 1)|


def pose_problem(pose: np.ndarray, source: str = "the pose") -> Optional[str]:
    """Why a 4x4 camera-to-world `pose` cannot be used, or None. Rule: every entry finite; the
    rotation block orthonormal with determinant +1 (rigid, no reflection); the bottom row
    (0, 0, 0, 1); the translation within +-WORLD_EXTENT_M metres."""
    pose = np.asarray(pose, dtype=np.float64)
    if pose.shape != (4, 4):
        return f"{source} is not a 4x4 matrix"
    if not np.all(np.isfinite(pose)):
        return f"{source} is not finite (tracking lost)"
    t = pose[:3, 3]
    if np.abs(t).max() > WORLD_EXTENT_M:
        return f"{source} places the camera {np.abs(t).max():.3g} m away, beyond {WORLD_EXTENT_M:g} m"
    R = pose[:3, :3]
    if (np.abs(R.T @ R - np.eye(3)).max() > ROTATION_TOLERANCE
            or np.abs(pose[3] - (0, 0, 0, 1)).max() > BOTTOM_ROW_TOLERANCE):
        return f"{source} is not a rigid transform"
    if np.linalg.det(R) < 0:   # orthonormal but mirrored: no camera moves like that
        return f"{source} is a reflection (determinant -1), not a rotation"
    return None


def rigid(pose: np.ndarray) -> np.ndarray:
    """A pose that passed `pose_problem` with its rotation block replaced by the nearest rotation
    (scipy's `Rotation.from_matrix`). Rule "one camera, one pose": a layout that stores 4x4
    matrices rounded to a few digits (7-Scenes) and one that stores quaternions (a bag) then give
    the same camera, to the last bits, instead of poses a millimetre apart."""
    out = np.array(pose, dtype=np.float64, copy=True)
    out[:3, :3] = Rotation.from_matrix(out[:3, :3]).as_matrix()
    out[3] = (0.0, 0.0, 0.0, 1.0)
    return out
