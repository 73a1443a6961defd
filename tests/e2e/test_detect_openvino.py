"""The OpenVINO runtime of the packaged SSD: its NumPy detection output on hand-made scores, the
same detections as cv2.dnn on real kitchen frames, and a converted-model cache that survives
corruption."""
from __future__ import annotations

import json
import shutil

import cv2
import numpy as np
import pytest

from sg3d.ingest.detect.choice import RUNTIME_ENV, detector_for, ssd_runtime
from sg3d.ingest.detect.models import (
    SSD_MODEL_FILE,
    SsdMobilenetDetector,
    packaged_model_dir,
)
from sg3d.ingest.detect.openvino import (
    MANIFEST,
    OpenVinoSsdDetector,
    _read_cached,
    converted_model,
    greedy_nms_per_class,
    ssd_detection_output,
)


def _scores(rows: dict[int, dict[int, float]], anchors: int, classes: int = 4) -> np.ndarray:
    s = np.zeros((anchors, classes), np.float32)
    for anchor, per_class in rows.items():
        for c, v in per_class.items():
            s[anchor, c] = v
    return s


def test_detection_output_suppresses_within_a_class_only_and_lists_best_first():
    boxes_yx = np.array([
        [0.10, 0.10, 0.50, 0.50],     # 0
        [0.11, 0.10, 0.51, 0.50],     # 1: same place as 0
        [0.60, 0.60, 0.90, 0.90],     # 2: elsewhere
        [0.10, 0.10, 0.50, 0.50],     # 3: same place as 0
    ], np.float32)
    scores = _scores({0: {1: 0.9, 2: 0.4}, 1: {1: 0.8, 2: 0.5}, 2: {1: 0.3}, 3: {3: 0.005}}, 4)
    boxes, ids, sc = ssd_detection_output(boxes_yx, scores)
    rows = [(int(c), round(float(s), 3)) for c, s in zip(ids, sc)]
    # class 1: anchor 1 overlaps anchor 0 (better) -> gone; class 2 keeps its best of the two;
    # class 3 is under the 0.01 floor; background (column 0) is never a class
    assert rows == [(1, 0.9), (2, 0.5), (1, 0.3)]
    assert boxes[0] == pytest.approx([0.10, 0.10, 0.50, 0.50])     # x1 y1 x2 y2
    assert boxes[2] == pytest.approx([0.60, 0.60, 0.90, 0.90])


def test_detection_output_keeps_the_best_overall_and_the_per_class_top_k():
    grid = np.arange(8) * 0.1 + 0.1
    centres = np.stack(np.meshgrid(grid, grid), axis=-1).reshape(-1, 2)[:60]
    boxes_yx = np.hstack([centres - 0.01, centres + 0.01]).astype(np.float32)   # disjoint boxes
    scores = np.zeros((60, 3), np.float32)
    scores[:, 1] = np.linspace(0.9, 0.3, 60)
    scores[:, 2] = np.linspace(0.85, 0.25, 60)
    _, ids, sc = ssd_detection_output(boxes_yx, scores, top_k=50, keep_top_k=70)
    assert len(sc) == 70
    assert (ids == 1).sum() <= 50 and (ids == 2).sum() <= 50
    kept = np.sort(sc)[::-1]
    dropped = np.setdiff1d(np.concatenate([scores[:50, 1], scores[:50, 2]]), sc)
    assert kept[-1] >= dropped.max()
    assert list(sc) == sorted(sc, reverse=True)      # best first, as OpenCV lists them


def test_greedy_nms_keeps_a_chain_link_whose_suppressor_was_suppressed():
    boxes = np.array([[6, 0, 16, 10], [0, 0, 10, 10], [3, 0, 13, 10], [3, 0, 13, 10]], np.float32)
    keep = greedy_nms_per_class(boxes, classes=[5, 5, 5, 9], rank=[2, 0, 1, 0], iou=0.4)
    # rank 1 overlaps rank 0 by 0.54 -> gone; rank 2 overlaps rank 0 by 0.25 only, and the gone
    # one no longer counts; the same box in another class is untouched
    assert keep.tolist() == [True, True, False, True]


def test_detection_output_of_nothing_is_empty():
    boxes, ids, sc = ssd_detection_output(np.zeros((5, 4), np.float32), np.zeros((5, 91), np.float32))
    assert boxes.shape == (0, 4) and len(ids) == 0 and len(sc) == 0


# --------------------------------------------------------------------------- real model

@pytest.fixture(scope="module")
def ov_cache(tmp_path_factory):
    pytest.importorskip("openvino", reason="the OpenVINO runtime is not installed")
    return tmp_path_factory.mktemp("ov-cache")


@pytest.fixture(scope="module")
def ov_ssd(ov_cache):
    return OpenVinoSsdDetector(cache_dir=ov_cache)


def test_openvino_and_opencv_give_the_same_detections_on_kitchen_frames(ov_ssd, kitchen_dir):
    cv_ssd = SsdMobilenetDetector()
    compared = 0
    for i in range(0, 1000, 50):
        image = cv2.imread(str(kitchen_dir / f"frame-{i:06d}.color.jpg"))
        a, b = cv_ssd.detect(image), ov_ssd.detect(image)
        assert [d.labels for d in a] == [d.labels for d in b], f"frame {i}"
        for x, y in zip(a, b):
            assert np.allclose(x.scores, y.scores, atol=0.02), f"frame {i}: {x.scores} vs {y.scores}"
            assert np.allclose(x.box, y.box, atol=2.0), f"frame {i}: {x.box} vs {y.box}"
        compared += len(a)
    assert compared >= 40            # the comparison saw real objects, not empty frames


def test_tiles_run_through_openvino_too(ov_ssd, kitchen_dir):
    image = cv2.imread(str(kitchen_dir / "frame-000000.color.jpg"))
    tile = np.ascontiguousarray(image[:280, :260])
    a = SsdMobilenetDetector()._candidates(tile)
    b = ov_ssd._candidates(tile)
    assert len(a[1]) == len(b[1]) == 100              # a busy tile: the keep_top_k cut applies
    assert np.array_equal(a[1], b[1])
    assert np.allclose(a[2], b[2], atol=0.02) and np.allclose(a[0], b[0], atol=2.0)


def test_the_cache_is_reused_and_a_corrupt_entry_is_rebuilt(ov_ssd, ov_cache, tmp_path):
    _ = ov_ssd.net                               # converted and cached by the detector
    entries = [p for p in (ov_cache / "openvino").iterdir() if not p.name.startswith(".")]
    assert len(entries) == 1
    entry = entries[0]
    manifest = json.loads((entry / MANIFEST).read_text())
    assert manifest["weights_sha256"] and manifest["openvino"]
    expected = {k: manifest[k] for k in ("format", "openvino", "weights_sha256")}
    assert _read_cached(entry, expected) is not None
    assert _read_cached(entry, dict(expected, openvino="0.0")) is None      # another runtime

    copy = tmp_path / "openvino" / entry.name
    shutil.copytree(entry, copy)
    with open(copy / "model.bin", "r+b") as f:   # a torn write
        f.truncate(1000)
    assert _read_cached(copy, expected) is None
    pb = packaged_model_dir() / SSD_MODEL_FILE
    model = converted_model(pb, tmp_path)
    assert len(model.outputs) == 2
    assert _read_cached(copy, expected) is not None                          # rewritten whole
    assert not [p for p in copy.parent.iterdir() if p.name.startswith(".tmp-")]


def test_runtime_choice_follows_the_environment(monkeypatch):
    monkeypatch.setenv(RUNTIME_ENV, "opencv")
    assert ssd_runtime() == "opencv"
    assert type(detector_for()) is SsdMobilenetDetector
    monkeypatch.setenv(RUNTIME_ENV, "tensorrt")
    with pytest.raises(ValueError, match=RUNTIME_ENV):
        detector_for()
