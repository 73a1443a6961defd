"""Frames kept past a live source's ring (`sg3d.ingest.readers.kept`)."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.readers import kept
from sg3d.ingest.readers.frames import Frame, FrameInfo


def _frame(i: int, seed: int = 0) -> Frame:
    rng = np.random.default_rng(seed + i)
    yy, xx = np.mgrid[0:48, 0:64]
    colour = np.stack([xx * 3 + 10 * i, yy * 4, 128 + 0 * xx], axis=-1).clip(0, 255).astype(np.uint8)
    depth = rng.uniform(0.4, 4.0, (48, 64)).astype(np.float32)
    depth[:4] = 0.0                                    # holes stay holes
    pose = np.eye(4)
    pose[:3, 3] = (i, 0.0, 0.0)
    K = np.array([[50.0, 0, 32], [0, 50.0, 24], [0, 0, 1]])
    return Frame(i, colour, depth, K, pose, FrameInfo(0.1 * i, f"cam-{i:06d}"))


def test_a_kept_frame_reads_back_as_kept():
    store = kept.KeptFrames()
    original = _frame(3)
    store.keep(original)
    back = store.frame(3)
    assert back is not None and back.name == "cam-000003" and back.timestamp == pytest.approx(0.3)
    np.testing.assert_array_equal(back.pose, original.pose)
    np.testing.assert_array_equal(back.K, original.K)
    # depth to the millimetre (the kept unit), holes kept
    assert np.max(np.abs(back.depth - original.depth)) <= kept.DEPTH_UNIT_M / 2 + 1e-6
    assert np.array_equal(back.depth == 0, original.depth == 0)
    # colour as a JPEG at quality 95 gives it back within a few levels
    assert np.mean(np.abs(back.color.astype(int) - original.color.astype(int))) < 2
    assert back.gray.shape == (48, 64)
    assert store.frame(4) is None


def test_depth_beyond_the_unit_range_and_nan_read_as_none():
    f = _frame(0)
    f.depth[10, 10], f.depth[11, 11] = np.nan, 70.0
    store = kept.KeptFrames()
    store.keep(f)
    back = store.frame(0)
    assert back is not None and back.depth[10, 10] == 0 and back.depth[11, 11] == 0


def test_the_oldest_frames_go_when_the_budget_is_spent():       # KEPT_MIB, both sides
    one = kept.encode_frame(_frame(0)).nbytes
    store = kept.KeptFrames(budget_mib=3.5 * one / (1 << 20))   # room for three of these frames
    for i in range(3):
        store.keep(_frame(i))
    assert len(store) == 3 and store.dropped == 0              # within the budget: all kept
    store.keep(_frame(3))
    assert store.dropped == 1 and 0 not in store and store.frame(0) is None
    assert all(i in store for i in (1, 2, 3)) and store.bytes <= store.budget


def test_a_frame_kept_twice_is_kept_once():
    store = kept.KeptFrames()
    store.keep(_frame(1))
    size = store.bytes
    store.keep(_frame(1, seed=5))
    assert len(store) == 1 and store.bytes == size


def test_a_live_source_reads_its_ring_first_then_what_it_kept():      # ring_or_kept
    from collections import deque

    from sg3d.ingest.readers.frames import FrameError

    store = kept.KeptFrames()
    store.keep(_frame(2))
    ring = deque(["item 8", "item 9"], maxlen=2)                      # frames 8 and 9 of 10 received
    assert kept.ring_or_kept(ring, 10, 9, "frame-9", 2, store) == ("item 9", None)
    item, frame = kept.ring_or_kept(ring, 10, 2, "frame-2", 2, store)
    assert item is None and frame is not None and frame.index == 2
    with pytest.raises(FrameError, match="no longer held"):
        kept.ring_or_kept(ring, 10, 3, "frame-3", 2, store)                 # past the ring, never kept
    with pytest.raises(FrameError, match="has not arrived"):
        kept.ring_or_kept(ring, 10, 10, "frame-10", 2, store)
