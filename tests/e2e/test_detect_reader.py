"""The reader thread that decodes frames ahead of selection and detection: the same frames, the
same pixels, the same frame choice, and a bad image still reported once, when it is used."""
from __future__ import annotations

import time

import numpy as np
import pytest

import sg3d.ingest.select.selection as selection
from sg3d.ingest.readers import open_sequence
from sg3d.ingest.readers.frames import FrameError, decoded_ahead
from sg3d.ingest.select.selection import choose_detected_frames


@pytest.fixture(scope="module")
def short_kitchen(kitchen_dir, tmp_path_factory):
    """The first 40 real kitchen frames, frame 7's colour image corrupt."""
    seq = tmp_path_factory.mktemp("kitchen40")
    (seq / "camera-intrinsics.txt").write_bytes((kitchen_dir / "camera-intrinsics.txt").read_bytes())
    for i in range(40):
        for ext in ("color.jpg", "depth.png", "pose.txt"):
            (seq / f"frame-{i:06d}.{ext}").write_bytes((kitchen_dir / f"frame-{i:06d}.{ext}").read_bytes())
    (seq / "frame-000007.color.jpg").write_bytes(b"not a jpeg at all" * 10)
    return seq


def test_frames_come_in_order_with_the_pixels_a_direct_decode_gives(short_kitchen):
    seq = open_sequence(short_kitchen)
    seen = []
    for frame in decoded_ahead(seq.frames(0, 12, lazy=True), ("color", "depth"), ahead=3):
        seen.append(frame.index)
        if frame.index == 7:
            assert seq.skipped == []                 # decoded ahead, but not reported yet
            with pytest.raises(FrameError, match="frame-000007"):
                _ = frame.color
            continue
        assert frame.is_loaded                       # the reader thread did the work
        direct = seq.frame(frame.index)
        assert np.array_equal(frame.color, direct.color)
        assert np.array_equal(frame.depth, direct.depth)
    assert seen == list(range(12))
    assert [name for name, _ in seq.skipped] == ["frame-000007"]


def test_a_consumer_that_stops_early_leaves_no_thread_behind(short_kitchen):
    import threading

    seq = open_sequence(short_kitchen)
    for frame in decoded_ahead(seq.frames(0, 40, lazy=True), ("gray",), ahead=4):
        if frame.index == 2:
            break
    deadline = time.monotonic() + 5
    while any(t.name.startswith("sg3d-decode") for t in threading.enumerate()) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(t.name.startswith("sg3d-decode") for t in threading.enumerate())


def test_the_kitchen_build_chooses_the_same_frames_with_and_without_the_reader(kitchen_dir, monkeypatch):
    seq = open_sequence(kitchen_dir)
    ahead = choose_detected_frames(seq, 0, 300).detected
    monkeypatch.setattr(selection, "decoded_ahead", lambda frames, what, ahead=4: frames)
    plain = choose_detected_frames(seq, 0, 300).detected
    assert ahead == plain and len(ahead) >= 20
