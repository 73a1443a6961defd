"""Which frames are detected (`ingest.coverage`): KGE's frames plus the sharpest frame of each
window KGE left without one; a changed KGE decision changes its own window's pick only."""
from __future__ import annotations

import numpy as np

from ingest import coverage


def _candidates(sharpness) -> list[coverage.Candidate]:
    return [coverage.Candidate(i, float(v)) for i, v in enumerate(sharpness)]


def test_budget_has_a_floor_and_never_exceeds_the_frames():
    assert coverage.frame_budget(1000, 0.15, 40) == 150
    assert coverage.frame_budget(100, 0.15, 40) == 40
    assert coverage.frame_budget(25, 0.15, 40) == 25


def test_windows_cover_every_frame_once_in_nearly_equal_counts():
    edges = coverage.window_edges(870, 130)
    sizes = np.diff(edges)
    assert edges[0] == 0 and edges[-1] == 870 and len(sizes) == 130
    assert sizes.min() >= 6 and sizes.max() <= 7
    assert list(coverage.window_edges(3, 10)) == [0, 1, 2, 3]      # never more windows than frames


def test_each_window_without_a_required_frame_gives_its_sharpest_frame():
    # 12 frames, 3 windows of 4: the sharpest of each is frame 1, 6 and 11
    sharp = [5, 9, 1, 1, 2, 2, 8, 2, 3, 3, 3, 7]
    assert coverage.choose_frames(_candidates(sharp), required=[], budget=3) == [1, 6, 11]
    # a required frame stands in for its window's pick; the other windows are unchanged
    assert coverage.choose_frames(_candidates(sharp), required=[4], budget=3) == [1, 4, 11]
    # two required frames in one window are both kept
    assert coverage.choose_frames(_candidates(sharp), required=[0, 2], budget=3) == [0, 2, 6, 11]


def test_ties_go_to_the_earlier_frame_and_input_order_does_not_matter():
    cands = _candidates([4, 4, 4, 4, 1, 1])
    assert coverage.choose_frames(cands, [], 2) == [0, 3]
    assert coverage.choose_frames(list(reversed(cands)), [], 2) == [0, 3]
    assert coverage.choose_frames([], [1, 2], 5) == []
    # a required frame that is not a sharp candidate is not detected
    assert 99 not in coverage.choose_frames(cands, [99], 2)


def test_one_changed_kge_decision_changes_at_most_two_picks():
    """Farthest-point sampling from the KGE frames shifts every later pick when one KGE frame
    moves; the window rule may change only the frame itself and its window's sharpest pick."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        n = int(rng.integers(50, 400))
        cands = _candidates(rng.uniform(10, 500, n))
        required = set(rng.choice(n, size=int(rng.integers(0, n // 8)), replace=False).tolist())
        budget = coverage.frame_budget(n)
        before = set(coverage.choose_frames(cands, required, budget))
        flipped = int(rng.integers(0, n))
        after = set(coverage.choose_frames(cands, required ^ {flipped}, budget))
        assert len(before ^ after) <= 2, (flipped, sorted(before ^ after))
        assert required <= before and (required ^ {flipped}) <= after


def test_a_kge_frame_that_moves_by_one_frame_changes_at_most_four_picks():
    rng = np.random.default_rng(11)
    n = 870
    cands = _candidates(rng.uniform(10, 500, n))
    required = sorted(rng.choice(np.arange(1, n - 1), size=54, replace=False).tolist())
    budget = coverage.frame_budget(n)
    before = set(coverage.choose_frames(cands, required, budget))
    for k in range(len(required)):
        moved = set(required[:k] + [required[k] + 1] + required[k + 1:])
        after = set(coverage.choose_frames(cands, moved, budget))
        assert len(before ^ after) <= 4
    assert budget <= len(before) <= budget + len(required)
