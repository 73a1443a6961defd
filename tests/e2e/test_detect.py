"""Detector: label map, top-k gathering + NMS on hand-made candidates, real SSD on a kitchen frame."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from sg3d.ingest.detect.choice import make_detector
from sg3d.ingest.detect.models import (
    COCO_LABELS_FILE,
    Detection,
    OnnxDetector,
    SsdMobilenetDetector,
    box_iou,
    detections_from_candidates,
    load_label_map,
)


def test_label_map_has_80_classes_with_tf_zoo_ids():
    labels = load_label_map(COCO_LABELS_FILE)
    assert len(labels) == 80
    assert len(set(labels.values())) == 80
    assert min(labels) == 1 and max(labels) == 90
    # ids the TF zoo leaves unused
    for unused in (12, 26, 29, 30, 45, 66, 68, 69, 71, 83):
        assert unused not in labels
    assert labels[1] == "person"
    assert labels[44] == "bottle"
    assert labels[47] == "cup"
    assert labels[62] == "chair"
    assert labels[67] == "dining table"
    assert labels[72] == "tv"
    assert labels[82] == "refrigerator"
    assert labels[90] == "toothbrush"


def test_box_iou():
    iou = box_iou(np.array([[0, 0, 10, 10]]), np.array([[0, 0, 10, 10], [5, 0, 15, 10], [20, 20, 30, 30]]))
    assert iou[0] == pytest.approx([1.0, 50 / 150, 0.0])


LABELS = {47: "cup", 51: "bowl", 62: "chair", 67: "dining table", 44: "bottle"}


def test_same_region_candidates_become_top_k_labels_of_one_object():
    boxes = np.array([
        [100, 100, 140, 150],   # cup, strong
        [101, 100, 141, 151],   # bowl, same region -> second label
        [100, 101, 140, 149],   # bottle, same region, weaker -> third label
        [102, 102, 139, 150],   # cup again, weaker duplicate -> suppressed by NMS
        [300, 200, 500, 400],   # chair elsewhere
        [100, 100, 140, 150],   # unknown class id 999 -> ignored
    ], dtype=float)
    class_ids = np.array([47, 51, 44, 47, 62, 999])
    scores = np.array([0.8, 0.3, 0.1, 0.5, 0.6, 0.99])
    dets = detections_from_candidates(boxes, class_ids, scores, LABELS)
    assert len(dets) == 2
    cup = next(d for d in dets if d.label == "cup")
    assert cup.labels == ["cup", "bowl", "bottle"]
    assert cup.scores == pytest.approx([0.8, 0.3, 0.1])
    assert cup.box == pytest.approx((100, 100, 140, 150))
    chair = next(d for d in dets if d.label == "chair")
    assert chair.labels == ["chair"]


def test_two_strong_classes_on_one_region_are_one_object_and_low_scores_are_dropped():
    boxes = np.array([[0, 0, 100, 100], [1, 1, 100, 100], [400, 400, 450, 450]], dtype=float)
    dets = detections_from_candidates(boxes, np.array([67, 62, 47]), np.array([0.5, 0.45, 0.2]), LABELS)
    assert len(dets) == 1                         # the cup at 0.2 is below the 0.23 threshold
    assert dets[0].labels == ["dining table", "chair"]


def test_distinct_overlapping_objects_survive():
    # a cup on a table: heavy containment but low IoU -> both objects stay
    boxes = np.array([[0, 0, 400, 300], [100, 50, 140, 100]], dtype=float)
    dets = detections_from_candidates(boxes, np.array([67, 47]), np.array([0.7, 0.6]), LABELS)
    assert sorted(d.label for d in dets) == ["cup", "dining table"]


def test_make_detector_choices(tmp_path):
    assert isinstance(make_detector(None), SsdMobilenetDetector)
    assert isinstance(make_detector("ssd-mobilenet-v2-coco"), SsdMobilenetDetector)
    assert make_detector({"kind": "ssd", "score_threshold": 0.4}).score_threshold == 0.4
    model = tmp_path / "mine.onnx"
    model.write_bytes(b"")
    (tmp_path / "mine.txt").write_text("background\nmug\nplate\n")
    onnx = make_detector(str(model))
    assert isinstance(onnx, OnnxDetector)
    assert onnx.label_map == {0: "background", 1: "mug", 2: "plate"}
    with pytest.raises(ValueError):
        make_detector("yolo-nonexistent")
    with pytest.raises(FileNotFoundError):
        make_detector(str(tmp_path / "other.onnx"))


@pytest.fixture(scope="module")
def ssd():
    return SsdMobilenetDetector()


def test_real_ssd_finds_chair_and_table_on_kitchen_frame(ssd, kitchen_dir):
    image = cv2.imread(str(kitchen_dir / "frame-000000.color.jpg"))
    assert image is not None
    h, w = image.shape[:2]
    dets = ssd.detect(image)
    labels = [d.label for d in dets]
    assert "chair" in labels
    assert "dining table" in labels
    for d in dets:
        assert isinstance(d, Detection)
        x1, y1, x2, y2 = d.box
        assert 0 <= x1 < x2 <= w and 0 <= y1 < y2 <= h
        assert d.score >= 0.23
        assert 1 <= len(d.labels) <= 5 and len(d.labels) == len(d.scores)
        assert list(d.scores) == sorted(d.scores, reverse=True)
    chair = max((d for d in dets if d.label == "chair"), key=lambda d: d.score)
    assert chair.score > 0.5
    # the chair at the left of the table in frame 0 stands in the left half of the image
    assert (chair.box[0] + chair.box[2]) / 2 < w / 2


def test_real_ssd_on_blank_image_finds_nothing_confident(ssd):
    dets = ssd.detect(np.full((480, 640, 3), 128, np.uint8))
    assert all(d.score < 0.5 for d in dets)


# --------------------------------------------------------------------------- recognition

def test_classifier_evidence_promotes_and_enriches_but_never_demotes():
    from sg3d.ingest.detect.recognize import fuse_with_classifier

    d = Detection((0, 0, 10, 10), ["bowl", "cup"], [0.30, 0.24])
    fused = fuse_with_classifier(d, [("coffee mug", 0.5), ("cup", 0.3), ("espresso", 0.1)], weight=0.5)
    # cup: 1 - (1 - 0.24) * (1 - 0.5 * 0.8) = 0.544; bowl keeps 0.30
    assert fused.labels == ["cup", "bowl"]
    assert fused.scores == pytest.approx([0.544, 0.30])
    unmapped = fuse_with_classifier(d, [("crate", 0.9)])
    assert unmapped.labels == d.labels and unmapped.scores == d.scores
    added = fuse_with_classifier(Detection((0, 0, 1, 1), ["tv"], [0.4]), [("monitor", 0.6)], weight=0.5)
    assert added.labels == ["tv"] and added.scores == pytest.approx([1 - 0.6 * 0.7])


def test_real_recognizer_on_a_kitchen_crop(ssd, kitchen_dir):
    pytest.importorskip("ai_edge_litert")
    from sg3d.ingest.detect.recognize import (
        EfficientNetRecognizer,
        RecognizingDetector,
        crop,
    )

    image = cv2.imread(str(kitchen_dir / "frame-000000.color.jpg"))
    table = next(d for d in ssd.detect(image) if d.label == "dining table")
    recognizer = EfficientNetRecognizer()
    top = recognizer.classify(crop(image, table.box))
    assert len(top) == 5 and all(0.0 <= p <= 1.0 for _, p in top)
    assert [p for _, p in top] == sorted((p for _, p in top), reverse=True)
    assert "dining table" in [name for name, _ in top]
    dets = RecognizingDetector(ssd, recognizer).detect(image)
    assert "dining table" in [d.label for d in dets]
    assert isinstance(make_detector({"kind": "ssd", "recognize": True}), RecognizingDetector)


# --------------------------------------------------------------------------- ONNX plug-in

def _write_constant_onnx_detector(folder, size=(640, 640)):
    """A real ONNX graph in OnnxDetector's output convention (N x 6: x1 y1 x2 y2 score class,
    corners normalised). Row 0's score is the mean of the network input, so it proves the image
    reached the model; the other rows are constants: a plate, an unknown class (7, ignored) and a
    mug below the 0.23 threshold."""
    from tests.onnx_writer import attr_int, model, node, tensor, value_info

    rows = np.array([[0.10, 0.20, 0.50, 0.60, 0.0, 3],
                     [0.60, 0.50, 0.90, 0.95, 0.8, 2],
                     [0.00, 0.00, 1.00, 1.00, 0.9, 7],
                     [0.30, 0.30, 0.40, 0.40, 0.1, 1]], np.float32)
    mask = np.zeros_like(rows)
    mask[0, 4] = 1.0
    path = folder / "mine.onnx"
    path.write_bytes(model(
        [node("ReduceMean", ["images"], ["m"], attr_int("keepdims", 0)),
         node("Mul", ["mask", "m"], ["s"]),
         node("Add", ["rows", "s"], ["det"])],
        [tensor("rows", rows), tensor("mask", mask)],
        [value_info("images", [1, 3, size[1], size[0]])], [value_info("det", list(rows.shape))]))
    (folder / "mine.labels.json").write_text('{"labels": {"1": "mug", "2": "plate", "3": "bowl"}}')
    return path


def test_onnx_plugin_runs_a_real_model_on_a_kitchen_frame(tmp_path, kitchen_dir):
    from sg3d.ingest.detect.choice import detector_for

    image = cv2.imread(str(kitchen_dir / "frame-000000.color.jpg"))
    h, w = image.shape[:2]
    path = _write_constant_onnx_detector(tmp_path)
    detector = make_detector(str(path))
    assert isinstance(detector, OnnxDetector)
    dets = sorted(detector.detect(image), key=lambda d: d.label)
    assert [d.label for d in dets] == ["bowl", "plate"]      # class 7 unknown, mug below 0.23
    bowl, plate = dets
    assert plate.box == pytest.approx((0.60 * w, 0.50 * h, 0.90 * w, 0.95 * h), abs=1e-3)
    assert plate.labels == ["plate"] and plate.scores == pytest.approx([0.8], abs=1e-6)
    assert bowl.box == pytest.approx((0.10 * w, 0.20 * h, 0.50 * w, 0.60 * h), abs=1e-3)
    # the model saw this image, resized to its 640x640 input and scaled to [0, 1]
    seen = cv2.resize(image, (640, 640)).mean() / 255.0
    assert bowl.score == pytest.approx(seen, abs=2e-3)
    # a black frame: the bowl's score is 0, so only the constant plate remains
    assert [d.label for d in detector.detect(np.zeros_like(image))] == ["plate"]
    # the build's own route to it (`--detector mine.onnx --score-threshold 0.85`)
    assert detector_for(str(path), score_threshold=0.85).detect(image) == []


def test_named_by_full_frame_needs_its_label_its_place_and_the_threshold():
    from sg3d.ingest.detect.models import named_by_full_frame

    labels = load_label_map()
    chair_id = next(k for k, v in labels.items() if v == "chair")
    tv_id = next(k for k, v in labels.items() if v == "tv")
    det = Detection((100, 100, 200, 300), ["chair", "bench"], [0.4, 0.1])
    boxes = np.array([[105, 95, 205, 305], [400, 100, 500, 300]], dtype=float)
    assert named_by_full_frame(det, boxes, np.array([chair_id, chair_id]), np.array([0.3, 0.9]), labels, 0.23)
    assert not named_by_full_frame(det, boxes, np.array([tv_id, chair_id]), np.array([0.9, 0.9]), labels, 0.23)
    assert not named_by_full_frame(det, boxes, np.array([chair_id, chair_id]), np.array([0.2, 0.9]), labels, 0.23)
    assert not named_by_full_frame(det, boxes[:0], np.array([], dtype=int), np.array([]), labels, 0.23)


def test_tiles_flag_what_only_they_named_on_a_real_frame(ssd, kitchen_dir):
    from sg3d.ingest.detect.models import TiledDetector

    image = cv2.imread(str(kitchen_dir / "frame-000000.color.jpg"))
    plain = ssd.detect(image)
    tiled = TiledDetector(ssd).detect(image)
    assert all(d.full_frame for d in plain)           # a plain detector's detections are its own
    assert any(d.full_frame for d in tiled) and len(tiled) >= len(plain)
    for d in tiled:
        same = [p for p in plain if p.label == d.label]
        overlaps = bool(same) and bool((box_iou(np.array(d.box), np.array([p.box for p in same])) >= 0.5).any())
        if overlaps:                                   # the full frame named it at that place
            assert d.full_frame, d
