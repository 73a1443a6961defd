"""Which frames are detected (`sg3d.ingest.select.coverage`): KGE's frames and the farthest new viewpoints,
each moved to the sharpest frame of its window, so a choice that moves a frame or two changes
nothing or its own window's frames only."""
from __future__ import annotations

import math

import numpy as np
import pytest

from sg3d.ingest.select import coverage


def _pose(x: float, yaw_deg: float = 0.0) -> np.ndarray:
    a = math.radians(yaw_deg)
    pose = np.eye(4)
    pose[:3, :3] = [[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]]
    pose[0, 3] = x
    return pose


def _candidates(sharpness, poses=None) -> list[coverage.Candidate]:
    poses = poses if poses is not None else [_pose(0.0)] * len(sharpness)
    return [coverage.Candidate(i, p, float(v)) for i, (v, p) in enumerate(zip(sharpness, poses))]


def test_budget_has_a_floor_and_never_exceeds_the_frames():
    assert coverage.frame_budget(1000, 0.15, 40) == 150
    assert coverage.frame_budget(100, 0.15, 40) == 40
    assert coverage.frame_budget(25, 0.15, 40) == 25


def test_farthest_viewpoints_keep_required_frames_then_take_the_newest_views_first():
    # frames 0-9 stand still at x=0; frame 10 stands 2 m away; frame 11 turns 90 degrees
    cands = _candidates([1.0] * 12, [_pose(0.0)] * 10 + [_pose(2.0), _pose(0.0, 90.0)])
    assert coverage.farthest_viewpoints(cands, required=[3], budget=3) == [3, 10, 11]
    # repeating the same view adds nothing: the choice stops rather than pick duplicates
    assert coverage.farthest_viewpoints(cands, required=[3], budget=12) == [3, 10, 11]


def test_viewpoint_distance_follows_its_formula():
    f = coverage.viewpoint_features([_pose(0.0), _pose(0.3, 0.0)])
    assert np.linalg.norm(f[1] - f[0]) == pytest.approx(0.3 / coverage.POSITION_SCALE_M)


def test_windows_cover_every_frame_once_in_nearly_equal_counts():
    edges = coverage.window_edges(870, 7)
    sizes = np.diff(edges)
    assert edges[0] == 0 and edges[-1] == 870 and len(sizes) == 124
    assert sizes.min() >= 7 and sizes.max() <= 8
    assert list(coverage.window_edges(3, 7)) == [0, 3]          # one window at least
    assert list(coverage.window_edges(10, 5)) == [0, 5, 10]


def test_a_choice_is_detected_as_its_windows_sharpest_frame():
    # 12 frames, windows of 4: the sharpest of each is frame 1, 6 and 11
    sharp = [5, 9, 1, 1, 2, 2, 8, 2, 3, 3, 3, 7]
    cands = _candidates(sharp)
    assert coverage.sharpest_in_windows(cands, [0], window=4) == [1]
    assert coverage.sharpest_in_windows(cands, [2, 4, 8], window=4) == [1, 6, 11]
    # two choices in one window: its two sharpest frames; the count of frames is kept
    assert coverage.sharpest_in_windows(cands, [0, 3, 9], window=4) == [0, 1, 11]
    # ties go to the earlier frame; input order does not matter; a non-candidate is dropped
    flat = _candidates([4, 4, 4, 4])
    assert coverage.sharpest_in_windows(list(reversed(flat)), [3, 99], window=4) == [0]
    assert coverage.sharpest_in_windows([], [1], window=4) == []


def test_a_choice_that_moves_a_few_frames_changes_at_most_two_detected_frames():
    """What pose noise does to KGE's anchors and the farthest-point picks (they move by 1-4
    frames): within a window nothing changes, across a window edge that window's frames only."""
    rng = np.random.default_rng(7)
    n = 870
    cands = _candidates(rng.uniform(10, 500, n))
    choices = sorted(rng.choice(np.arange(4, n - 4), size=130, replace=False).tolist())
    before = set(coverage.sharpest_in_windows(cands, choices))
    unchanged = 0
    for k in range(len(choices)):
        for shift in (-4, -1, 1, 4):
            moved = choices[:k] + [choices[k] + shift] + choices[k + 1:]
            if len(set(moved)) < len(moved):
                continue
            after = set(coverage.sharpest_in_windows(cands, moved))
            assert len(before ^ after) <= 2
            unchanged += after == before
    assert unchanged > 0


def test_choose_frames_detects_the_budget_and_moves_each_choice_inside_its_window():
    rng = np.random.default_rng(3)
    n = 300
    poses = [_pose(0.01 * i, 0.3 * i) for i in range(n)]
    cands = _candidates(rng.uniform(10, 500, n), poses)
    required = [0, 40, 80, 120, 160, 200, 240, 280]
    budget = coverage.frame_budget(n)
    chosen = coverage.choose_frames(cands, required, budget)
    assert len(chosen) == budget
    edges = coverage.window_edges(n, coverage.SNAP_WINDOW)
    windows = np.searchsorted(edges, chosen, side="right") - 1
    for r in required:      # every KGE frame's window is detected
        assert np.searchsorted(edges, r, side="right") - 1 in windows


# --------------------------------------------------------------------------- the defaults, on both sides

def test_the_default_budget_is_15_percent_and_at_least_40_frames():   # DEFAULT_FRACTION, MIN_FRAMES
    assert coverage.frame_budget(1000) == 150
    assert coverage.frame_budget(300) == 45
    assert coverage.frame_budget(200) == 40
    assert coverage.frame_budget(30) == 30


def test_30_cm_or_a_quarter_chord_of_turning_is_one_unit_of_new_view():   # POSITION_SCALE_M, DIRECTION_SCALE
    moved = coverage.viewpoint_features([_pose(0.0), _pose(0.3)])
    assert np.linalg.norm(moved[1] - moved[0]) == pytest.approx(1.0)
    chord = 2 * math.degrees(math.asin(0.125))                         # the optical axis moves 0.25
    turned = coverage.viewpoint_features([_pose(0.0), _pose(0.0, chord)])
    assert np.linalg.norm(turned[1] - turned[0]) == pytest.approx(1.0)


def test_a_choice_moves_within_a_window_of_5_sharp_frames():          # SNAP_WINDOW
    sharp = [1, 1, 1, 1, 9, 1, 1, 1, 1, 1, 1, 1, 1, 1, 9]
    cands = _candidates(sharp)
    assert coverage.sharpest_in_windows(cands, [0]) == [4]
    assert coverage.sharpest_in_windows(cands, [5]) == [5]            # the next window holds no 9
    assert coverage.sharpest_in_windows(cands, [10]) == [14]


def test_a_live_budget_is_a_share_of_the_recording_not_of_the_frames_tracking_took():   # recording_budget
    from sg3d.ingest.select.coverage import MIN_FRAMES, frame_budget, recording_budget

    # every frame judged: the build's budget over the sharp ones
    assert recording_budget(870, 1000, 1000) == frame_budget(870) == 130
    # a camera whose tracker took 464 of 1,000 frames, 400 of them sharp: the recording holds ~862
    assert recording_budget(400, 464, 1000) == frame_budget(862) == 129
    assert recording_budget(400, 464, 464) == frame_budget(400) == 60      # a budget of the judged ones
    # never more than there are to choose from, nor a budget for nothing
    assert recording_budget(30, 30, 1000) == 30
    assert recording_budget(MIN_FRAMES + 5, 500, 5000) == MIN_FRAMES + 5
    assert recording_budget(0, 0, 1000) == 0
