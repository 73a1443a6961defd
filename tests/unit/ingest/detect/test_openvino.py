"""The OpenVINO backend's candidate selection (`ssd_detection_output`), the DetectionOutput rules of
the SSD's text graph, on hand-made anchors (no model is converted or loaded)."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.detect.openvino import ssd_detection_output


def _anchors(scores_by_class: list[list[float]], boxes=None):
    """Anchors (ymin xmin ymax xmax) on a grid of small disjoint boxes, and their [A, classes] scores
    (class 0 is the background)."""
    n = max(len(s) for s in scores_by_class)
    if boxes is None:
        k = np.arange(n)
        y, x = (k // 16) * 0.06, (k % 16) * 0.06
        boxes = np.stack([y, x, y + 0.05, x + 0.05], axis=1)
    scores = np.zeros((n, len(scores_by_class) + 1), np.float32)
    for c, s in enumerate(scores_by_class):
        scores[:len(s), c + 1] = s
    return np.asarray(boxes, np.float32), scores


def test_a_candidate_scores_above_0_01():                             # CONFIDENCE_THRESHOLD
    boxes, ids, scores = ssd_detection_output(*_anchors([[0.011, 0.009]]))
    assert len(ids) == 1 and scores[0] == np.float32(0.011)


def test_one_class_candidates_overlapping_60_percent_are_one():        # DETECTION_NMS_IOU
    def kept(shift):                                                    # IoU (0.1 - s) / (0.1 + s)
        boxes = [[0.0, 0.0, 0.1, 0.1], [0.0, shift, 0.1, shift + 0.1]]
        return len(ssd_detection_output(*_anchors([[0.9, 0.8]], boxes))[1])
    assert kept(0.03) == 2            # IoU 0.54
    assert kept(0.02) == 1            # IoU 0.67


def test_a_class_keeps_its_100_best_candidates():                     # PER_CLASS_TOP_K
    assert len(ssd_detection_output(*_anchors([list(np.linspace(0.9, 0.5, 120))]))[1]) == 100
    # its 100 best lie on one box (NMS keeps one of them); 50 weaker ones elsewhere are not considered
    k = np.arange(150)
    boxes = np.where((k < 100)[:, None], [[0.0, 0.0, 0.05, 0.05]],
                     np.stack([0.1 + (k // 16) * 0.06, (k % 16) * 0.06, 0.15 + (k // 16) * 0.06,
                               (k % 16) * 0.06 + 0.05], axis=1))
    assert len(ssd_detection_output(*_anchors([list(np.linspace(0.9, 0.5, 150))], boxes))[1]) == 1


def test_all_classes_keep_their_100_best_candidates():                # KEEP_TOP_K
    two = _anchors([list(np.linspace(0.9, 0.5, 70)), list(np.linspace(0.89, 0.49, 70))])
    assert len(ssd_detection_output(*two)[1]) == 100
