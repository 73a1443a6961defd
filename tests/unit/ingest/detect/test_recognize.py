"""Recognition of proposed regions (`sg3d.ingest.detect.recognize`): crops, the classifier's top-n and
its weight in the fused labels; a stand-in interpreter replaces the tflite model."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.detect.models import Detection
from sg3d.ingest.detect.recognize import EfficientNetRecognizer, crop, fuse_with_classifier


def test_a_crop_takes_a_tenth_more_of_the_box_on_every_side():        # CROP_MARGIN
    image = np.zeros((480, 640, 3), np.uint8)
    assert crop(image, (100, 100, 200, 150)).shape == (60, 120, 3)


def test_the_classifier_counts_half():                                 # CLASSIFIER_WEIGHT
    chair = Detection((0, 0, 10, 10), ["chair"], [0.4])
    fused = fuse_with_classifier(chair, [("folding chair", 0.6)])
    assert fused.scores[0] == pytest.approx(1 - 0.6 * (1 - 0.5 * 0.6))    # 0.58
    # it promotes a second label over the first when it is sure enough
    bench = Detection((0, 0, 10, 10), ["bench", "chair"], [0.5, 0.3])
    assert fuse_with_classifier(bench, [("folding chair", 0.6)]).label == "chair"   # 0.51 beats 0.5
    assert fuse_with_classifier(bench, [("folding chair", 0.5)]).label == "bench"   # 0.475


class _Interpreter:
    """A 1000-class classifier answering fixed probabilities: class 0 most likely, then 1, ..."""

    def __init__(self):
        self.probs = np.linspace(0.2, 0.0, 1000)

    def get_input_details(self):
        return [{"shape": [1, 32, 32, 3], "index": 0, "dtype": np.uint8}]

    def get_output_details(self):
        return [{"index": 1, "quantization": (0.0, 0)}]

    def set_tensor(self, index, value):
        pass

    def invoke(self):
        pass

    def get_tensor(self, index):
        return self.probs[None]


def test_the_classifier_gives_its_5_best_names():                      # CLASSIFIER_TOP_N
    rec = EfficientNetRecognizer()
    rec._interpreter, rec._names = _Interpreter(), [f"class {i}" for i in range(1000)]
    assert [name for name, _ in rec.classify(np.zeros((40, 40, 3), np.uint8))] == [f"class {i}" for i in range(5)]
