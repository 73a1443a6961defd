"""The room's cloud (`sg3d.ingest.discover.room_cloud`): a view's small depth lifted to points and normals."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.discover.room_cloud import view_points
from sg3d.ingest.objects.existence import View

K = np.array([[100.0, 0, 80], [0, 100.0, 60], [0, 0, 1]])


def _view(depth: np.ndarray) -> View:
    return View(0, K, np.eye(4), (160, 120), depth.astype(np.float32))


def test_depth_is_used_up_to_4_m():                                    # MAX_RANGE_M
    assert len(view_points(_view(np.full((30, 40), 3.9)), np.eye(3), 0.0)[0]) == 1200
    assert len(view_points(_view(np.full((30, 40), 4.1)), np.eye(3), 0.0)[0]) == 0


def test_a_normal_is_taken_across_a_step_of_5_percent_plus_2_cm():    # NORMAL_JUMP_REL, NORMAL_JUMP_M
    def without_normal(step: float) -> int:
        depth = np.full((30, 40), 1.0)
        depth[:, 20:] += step
        _, normals = view_points(_view(depth), np.eye(3), 0.0)
        return int((np.linalg.norm(normals, axis=1) == 0).sum())
    border = 2 * 40 + 2 * 28                  # the grid's own edge never has a normal
    assert without_normal(0.065) == border    # 1 m away: a step under 7 cm is one surface
    assert without_normal(0.075) == border + 2 * 28
