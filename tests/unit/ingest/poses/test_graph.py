"""Pose-graph optimisation (`sg3d.ingest.poses.graph`, GTSAM): how far a loop closure that disagrees
with the odometry pulls a pose. An odometry fit is good to 1 cm and 0.01 rad; a loop closure's edge
is met halfway while it stays within the Huber kernel's 1.345 sigmas, and counts less beyond."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sg3d.ingest.poses.graph import optimise_pose_graph


def _pose(x: float = 0.0, yaw_deg: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("z", yaw_deg, degrees=True).as_matrix()
    T[0, 3] = x
    return T


def _second(loop: np.ndarray) -> np.ndarray:
    """Frame 1 after optimising: odometry says 1 m ahead of frame 0, the loop closure `loop`."""
    return optimise_pose_graph({0: _pose(), 1: _pose(1.0)}, [(0, 1, _pose(1.0), False), (0, 1, loop, True)], 0)[1]


def test_a_loop_closure_1_2_cm_off_each_edge_is_met_halfway():         # TRANSLATION_SIGMA
    assert _second(_pose(1.024))[0, 3] == pytest.approx(1.012, abs=1e-5)      # 1.2 sigma on each edge
    assert _second(_pose(1.030))[0, 3] == pytest.approx(1.01342, abs=1e-5)   # 1.5: down-weighted


def test_a_loop_closure_0_7_degrees_off_each_edge_is_met_halfway():    # ROTATION_SIGMA
    def yaw(T):
        return Rotation.from_matrix(T[:3, :3]).as_euler("zyx", degrees=True)[0]
    assert yaw(_second(_pose(1.0, 1.4))) == pytest.approx(0.7, abs=1e-3)     # 1.22 sigma
    assert yaw(_second(_pose(1.0, 1.7))) == pytest.approx(0.769, abs=1e-3)   # 1.48: down-weighted
