"""Associating detections across the frames of a keyframe group by 3-D position."""
from __future__ import annotations

import pytest

from ingest.detect import Detection
from ingest.tracks import FrameDetection, associate, fuse_labels


def fd(frame, labels, scores, position, extent=0.0):
    return FrameDetection(frame, Detection((0, 0, 1, 1), list(labels), list(scores)), position, extent)


def by_label(tracks):
    return {t.label: t for t in tracks}


def test_two_cups_and_a_table_over_three_frames():
    dets = [
        fd(10, ["cup"], [0.8], (0.00, 0.00, 0.80)),
        fd(10, ["cup"], [0.6], (0.30, 0.00, 0.80)),            # a second cup 30 cm away
        fd(10, ["dining table"], [0.7], (0.20, 0.10, 0.70), extent=1.6),
        fd(11, ["cup"], [0.7], (0.29, 0.02, 0.81)),            # order swapped in this frame
        fd(11, ["cup"], [0.9], (0.02, -0.01, 0.79)),
        fd(11, ["dining table"], [0.6], (0.55, 0.20, 0.72), extent=1.6),   # mean moved 37 cm
        fd(12, ["cup", "bowl"], [0.5, 0.4], (0.01, 0.01, 0.80)),
    ]
    tracks = associate(dets)
    assert len(tracks) == 3
    cups = sorted((t for t in tracks if t.label == "cup"), key=lambda t: t.position[0])
    assert [t.frames for t in cups] == [[10, 11, 12], [10, 11]]
    assert cups[0].position == pytest.approx((0.01, 0.0, 0.7967), abs=0.01)
    table = next(t for t in tracks if t.label == "dining table")
    assert table.frames == [10, 11]


def test_far_apart_or_incompatible_labels_start_new_tracks():
    dets = [
        fd(1, ["cup"], [0.8], (0.0, 0.0, 0.8)),
        fd(2, ["cup"], [0.8], (1.0, 0.0, 0.8)),        # 1 m away: another cup
        fd(3, ["chair"], [0.8], (0.02, 0.0, 0.8)),     # same place, unrelated label
        fd(4, ["bowl", "cup"], [0.5, 0.45], (0.01, 0.0, 0.8)),   # cup among its labels: joins
    ]
    tracks = associate(dets)
    assert len(tracks) == 3
    first = next(t for t in tracks if 1 in t.frames)
    assert first.frames == [1, 4]


def test_one_detection_per_track_per_frame():
    dets = [
        fd(1, ["cup"], [0.8], (0.0, 0.0, 0.8)),
        fd(2, ["cup"], [0.8], (0.05, 0.0, 0.8)),
        fd(2, ["cup"], [0.7], (0.10, 0.0, 0.8)),       # both near the track; only one may join
    ]
    tracks = associate(dets)
    assert len(tracks) == 2
    assert all(len(t.members) == t.n_frames for t in tracks)


def test_fuse_labels_means_over_frames():
    members = [
        fd(1, ["cup", "bowl"], [0.6, 0.3], (0, 0, 0)),
        fd(2, ["cup"], [0.8], (0, 0, 0)),
        fd(3, ["bowl", "cup", "vase"], [0.9, 0.4, 0.2], (0, 0, 0)),
    ]
    labels, scores = fuse_labels(members)
    assert labels == ["cup", "bowl", "vase"]
    assert scores == pytest.approx([(0.6 + 0.8 + 0.4) / 3, (0.3 + 0.9) / 3, 0.2 / 3])
    assert fuse_labels(members, top_k=1) == (["cup"], [pytest.approx(0.6)])
    assert fuse_labels([]) == ([], [])
