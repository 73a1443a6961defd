"""Detections from raw candidates (`sg3d.ingest.detect.models`): thresholds, NMS, top-k labels, tiles.
No network is loaded: candidates are hand-made, and the one detector test feeds a stand-in net."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.detect.models import (
    SsdMobilenetDetector,
    cut_by_tile,
    detections_from_candidates,
    tile_windows,
)

LABELS = {1: "chair", 2: "couch", 3: "bench"}


def _labels(boxes, ids, scores) -> list[list[str]]:
    found = detections_from_candidates(np.array(boxes, float), np.array(ids), np.array(scores), LABELS)
    return [d.labels for d in found]


def _pair(x: float):
    """Two 100 px boxes, the second shifted x px: IoU (100 - x) / (100 + x)."""
    return [[0, 0, 100, 100], [x, 0, x + 100, 100]]


def test_a_detection_scores_0_23_at_least():                          # SCORE_THRESHOLD
    assert _labels([[0, 0, 50, 50]], [1], [0.24]) == [["chair"]]
    assert _labels([[0, 0, 50, 50]], [1], [0.22]) == []


def test_boxes_of_one_class_overlapping_half_are_one_object():        # NMS_IOU
    assert _labels(_pair(37), [1, 1], [0.9, 0.8]) == [["chair"], ["chair"]]     # IoU 0.46
    assert _labels(_pair(28), [1, 1], [0.9, 0.8]) == [["chair"]]                # IoU 0.56


def test_boxes_of_two_classes_overlapping_70_percent_are_one_object():   # SAME_REGION_IOU
    assert _labels(_pair(14), [1, 2], [0.9, 0.8]) == [["chair", "couch"]]      # IoU 0.75
    assert _labels(_pair(21), [1, 2], [0.9, 0.8]) == [["chair"], ["couch"]]    # IoU 0.65


def test_a_second_label_scores_0_05_at_least():                        # CANDIDATE_MIN_SCORE
    box = [[0, 0, 100, 100]] * 2
    assert _labels(box, [1, 3], [0.9, 0.06]) == [["chair", "bench"]]
    assert _labels(box, [1, 3], [0.9, 0.04]) == [["chair"]]


def test_frames_are_cut_into_3_by_2_tiles_widened_by_a_fifth():        # TILE_GRID, TILE_OVERLAP
    tiles = tile_windows(640, 480)
    assert len(tiles) == 6
    assert tiles[0] == (0, 0, 235, 264) and tiles[4] == (192, 216, 448, 480)


def test_a_box_within_2_px_of_a_tiles_inner_edge_is_cut():             # TILE_EDGE_PX
    inner_left = (True, False, False, False)
    assert list(cut_by_tile(np.array([[1.9, 10, 50, 50], [2.1, 10, 50, 50]]), (200, 200), inner_left)) == [True, False]


class _Net:
    """A stand-in for the SSD: records the blob it is given, answers one chair."""

    def setInput(self, blob):
        self.blob = blob

    def forward(self):
        return np.array([[[[0, 62, 0.9, 0.1, 0.1, 0.5, 0.5]]]], np.float32)


def test_the_ssd_sees_the_frame_at_300_by_300():                       # SSD_INPUT_SIZE
    detector = SsdMobilenetDetector(num_threads=1)
    detector._net = net = _Net()
    (found,) = detector.detect(np.zeros((480, 640, 3), np.uint8))
    assert net.blob.shape == (1, 3, 300, 300)
    assert np.allclose(found.box, (64, 48, 320, 240)) and found.labels[0] == "chair"
