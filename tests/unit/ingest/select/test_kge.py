"""KGE: overlap (Eq. 5-6) on synthetic frames with known answers, and Algorithm 1 (the real
kitchen: tests/quality/kitchen/test_kitchen_ingest.py)."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.readers import quaternion_to_matrix
from sg3d.ingest.readers.frames import Frame, FrameInfo
from sg3d.ingest.select.kge import KeyframeGrouper, overlap

W, H = 100, 50
K = np.array([[50.0, 0, 49.5], [0, 50.0, 24.5], [0, 0, 1]])
STEP_PX = 7           # image shift between consecutive synthetic frames, in pixels
DEPTH = 1.0           # a wall 1 m in front of every camera


def _base_pose() -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = quaternion_to_matrix(np.array([0.1, -0.2, 0.3, 0.9]))
    T[:3, 3] = (1.0, -2.0, 0.5)
    return T


def _frame(i: int, shift_m: float = 0.0, pose: np.ndarray | None = None) -> Frame:
    if pose is None:
        pose = _base_pose()
        # move along the camera's own x axis, parallel to the wall
        pose[:3, 3] = pose[:3, 3] + pose[:3, 0] * shift_m
    depth = np.full((H, W), DEPTH, np.float32)
    color = np.zeros((H, W, 3), np.uint8)
    return Frame(i, color, depth, K, pose, FrameInfo(i / 30.0, f"synthetic-{i}"))


def _slide(i: int) -> Frame:
    # STEP_PX pixels of image motion per frame at the wall's depth
    return _frame(i, shift_m=i * STEP_PX * DEPTH / K[0, 0])


def test_overlap_with_itself_is_one():
    f = _frame(0)
    assert overlap(f, f, rng=np.random.default_rng(1)) == pytest.approx(1.0)


def test_overlap_with_a_far_away_or_turned_camera_is_zero():
    f = _frame(0)
    far = _base_pose()
    far[:3, 3] += far[:3, 0] * 100.0 + far[:3, 1] * 20.0  # 100 m sideways, 20 m down
    assert overlap(f, _frame(1, pose=far)) == pytest.approx(0.0)
    turned = _base_pose()
    turned[:3, :3] = turned[:3, :3] @ np.diag([-1.0, 1.0, -1.0])  # looking away: points behind it
    assert overlap(f, _frame(2, pose=turned)) == 0.0


def test_overlap_of_a_sideways_shift_matches_geometry():
    # 30 px of a 100 px wide view slide out: 70 % stays
    got = overlap(_frame(0), _frame(1, shift_m=30 * DEPTH / K[0, 0]), n_points=5000)
    assert got == pytest.approx(0.70, abs=1e-9)  # all 5000 pixels used: exact
    sampled = overlap(_frame(0), _frame(1, shift_m=30 * DEPTH / K[0, 0]), n_points=1000,
                      rng=np.random.default_rng(5))
    assert sampled == pytest.approx(0.70, abs=0.05)


def test_overlap_is_deterministic_given_a_seed_and_ignores_invalid_depth():
    a = _frame(0)
    a.depth[:, 50:] = 0  # right half without depth: only the left half is sampled
    b = _frame(1, shift_m=30 * DEPTH / K[0, 0])
    r1 = overlap(a, b, rng=np.random.default_rng(7))
    r2 = overlap(a, b, rng=np.random.default_rng(7))
    assert r1 == r2
    assert r1 == pytest.approx(0.4, abs=0.05)  # 20 of the 50 sampled columns stay in view


def _algorithm_1(n: int, ov, t_key: float, t_anchor: float) -> list[list[int]]:
    """Algorithm 1 transcribed line by line, on frame numbers and an overlap function."""
    groups = []
    keyframe = anchor = 0
    current = [keyframe]
    for curr in range(1, n):
        overlap_key = ov(keyframe, curr)
        overlap_anchor = ov(anchor, curr)
        if overlap_key < t_key:
            groups.append(current)
            keyframe = anchor = curr
            current = [keyframe]
            continue
        if overlap_anchor < t_anchor:
            anchor = curr
            current.append(anchor)
    groups.append(current)  # finish()
    return groups


def test_grouper_implements_algorithm_1():
    n = 40

    def analytic(i, j):
        return max(0.0, 1 - abs(j - i) * STEP_PX / W)

    expected = _algorithm_1(n, analytic, 0.2, 0.68)
    grouper = KeyframeGrouper(t_key=0.2, t_anchor=0.68, n_points=W * H)
    groups = list(grouper.feed(_slide(i) for i in range(n)))
    assert [[f.index for f in g.frames] for g in groups] == expected
    assert [g.index for g in groups] == list(range(len(expected)))
    assert expected[0] == [0, 5, 10]  # sanity of the scenario itself: anchors every 5, keyframe at 12
    assert grouper.n_keyframes == len(expected)
    assert grouper.n_anchors == sum(len(g) - 1 for g in expected)


def test_grouper_with_other_thresholds():
    n = 30

    def analytic(i, j):
        return max(0.0, 1 - abs(j - i) * STEP_PX / W)

    expected = _algorithm_1(n, analytic, 0.5, 0.9)
    groups = list(KeyframeGrouper(t_key=0.5, t_anchor=0.9, n_points=W * H).feed(_slide(i) for i in range(n)))
    assert [[f.index for f in g.frames] for g in groups] == expected


# --------------------------------------------------------------------------- the defaults, on both sides

def test_default_thresholds_start_a_group_below_20_percent_overlap_and_an_anchor_below_68():
    # DEFAULT_T_KEY, DEFAULT_T_ANCHOR: frames 7 px apart overlap 93, 86, ... 30 (5 apart), 16 (12 apart) %
    groups = list(KeyframeGrouper(n_points=W * H).feed(_slide(i) for i in range(40)))
    assert [[f.index for f in g.frames] for g in groups] == [[0, 5, 10], [12, 17, 22], [24, 29, 34], [36]]


def test_overlap_is_estimated_on_1000_samples_by_default():            # DEFAULT_POINTS
    shifted = _frame(1, shift_m=30 * DEPTH / K[0, 0])
    assert overlap(_frame(0), shifted) == 0.702          # 702 of the 1000 pixels drawn by seed 0
