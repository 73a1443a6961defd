"""The check every camera pose passes (`sg3d.ingest.readers.pose_check`), on hand-made matrices."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.readers.pose_check import pose_problem


def test_a_rotation_may_be_off_orthonormal_by_a_thousandth():          # ROTATION_TOLERANCE
    def scaled(e):                      # R^T R - I = (1 + e)^2 - 1 on the diagonal
        pose = np.eye(4)
        pose[:3, :3] *= 1 + e
        return pose
    assert pose_problem(scaled(0.00045)) is None                        # 0.0009
    assert pose_problem(scaled(0.00055)) == "the pose is not a rigid transform"   # 0.0011


def test_the_bottom_row_may_be_off_by_a_millionth():                    # BOTTOM_ROW_TOLERANCE
    def bottom(e):
        pose = np.eye(4)
        pose[3, 3] = 1 + e
        return pose
    assert pose_problem(bottom(0.9e-6)) is None
    assert pose_problem(bottom(1.1e-6)) == "the pose is not a rigid transform"
