"""Pose continuity (`sg3d.ingest.readers.pose_check.motion_problem` and `implausible_motion`), on
hand-made poses: both sides of every threshold, and which frames of a broken path are named."""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.ingest.readers.pose_check import (
    MAX_SPEED_M_S,
    MAX_TURN_RATE_DEG_S,
    MIN_STEP_S,
    STEP_SLACK_DEG,
    STEP_SLACK_M,
    implausible_motion,
    motion_problem,
)

HZ30 = 1.0 / 30.0


def at(x: float = 0.0, turn_deg: float = 0.0) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_euler("y", turn_deg, degrees=True).as_matrix()
    pose[0, 3] = x
    return pose


def test_the_thresholds_are_what_the_comments_say():
    # a change of a bound is a decision: this pins the figures the comments justify
    assert (MAX_SPEED_M_S, MAX_TURN_RATE_DEG_S, STEP_SLACK_M, STEP_SLACK_DEG) == (10.0, 720.0, 0.1, 5.0)
    assert MIN_STEP_S == 1.0 / 60.0


def test_a_step_may_be_as_long_as_the_top_speed_allows():                 # MAX_SPEED_M_S, STEP_SLACK_M
    limit = MAX_SPEED_M_S * HZ30 + STEP_SLACK_M                            # 0.433 m at 30 Hz
    assert motion_problem(at(0), at(limit * 0.99), HZ30) is None
    why = motion_problem(at(0), at(limit * 1.01), HZ30)
    assert why is not None and "jumps" in why and "at most 10 m/s" in why


def test_the_slack_alone_bounds_a_step_in_no_time():                       # STEP_SLACK_M, MIN_STEP_S
    limit = MAX_SPEED_M_S * MIN_STEP_S + STEP_SLACK_M                      # equal timestamps: 60 Hz
    assert motion_problem(at(0), at(limit * 0.99), 0.0) is None
    assert motion_problem(at(0), at(limit * 1.01), 0.0) is not None
    # out-of-order timestamps count by their size, not their sign
    assert motion_problem(at(0), at(0.3), -HZ30) is None


def test_a_longer_gap_allows_a_longer_step():                              # the bound grows with dt
    assert motion_problem(at(0), at(5.0), 0.5) is None                     # 5.1 m allowed in 0.5 s
    assert motion_problem(at(0), at(5.0), 0.4) is not None                 # 4.1 m in 0.4 s


def test_a_turn_may_be_as_fast_as_the_top_rate_allows():                  # MAX_TURN_RATE_DEG_S, STEP_SLACK_DEG
    limit = MAX_TURN_RATE_DEG_S * HZ30 + STEP_SLACK_DEG                    # 29 deg at 30 Hz
    assert motion_problem(at(0), at(0, limit - 0.2), HZ30) is None
    why = motion_problem(at(0), at(0, limit + 0.2), HZ30)
    assert why is not None and "turns" in why and "720 deg/s" in why


def test_the_sample_rooms_fastest_steps_pass():
    # kitchen 1.09 m/s and 1.4 deg per frame, living room 1.30 m/s and 1.6 deg per frame
    assert motion_problem(at(0), at(0.044, 1.6), HZ30) is None


def _path(n: int = 100) -> list[np.ndarray]:
    return [at(0.01 * i, 0.5 * i) for i in range(n)]


def _names(n: int = 100) -> list[str]:
    return [f"frame-{i:06d}" for i in range(n)]


def test_a_shifted_block_is_named_and_the_path_around_it_kept():
    poses = _path()
    for i in range(76, 84):
        poses[i] = poses[i].copy()
        poses[i][0, 3] += 50.0
    bad = implausible_motion(poses, [i * HZ30 for i in range(100)], _names())
    assert sorted(bad) == list(range(76, 84))
    assert "jumps 50 m" in bad[80] and "from frame-000075" in bad[80]


def test_a_glitch_in_the_first_frame_names_the_first_frame():
    poses = _path()
    poses[0] = at(0, 180.0)
    bad = implausible_motion(poses, [i * HZ30 for i in range(100)], _names())
    assert list(bad) == [0] and "turns" in bad[0] and "to frame-000001" in bad[0]


def test_a_plausible_path_and_missing_poses_name_nothing():
    poses: list = _path()
    poses[10] = poses[11] = None               # unusable poses are named elsewhere
    assert implausible_motion(poses, [i * HZ30 for i in range(100)], _names()) == {}
    assert implausible_motion([], [], []) == {}
