"""Spurious detection rejection (paper Sec. IV-C), the detection side: classes that cannot
belong to a persistent indoor scene graph are dropped from each frame's detections."""
from __future__ import annotations

from typing import Iterable

from sg3d.ingest.detect.models import Detection

# COCO classes that cannot be part of a persistent indoor scene graph: outdoor things and
# things that move by themselves (the paper's "road, sky, building, moving objects"). Pets and
# people move away between visits, so a graph that keeps them would hold stale entries.
IRRELEVANT_CLASSES = frozenset({
    "person",
    "bicycle", "car", "motorcycle", "airplane", "bus", "train", "truck", "boat",
    "traffic light", "fire hydrant", "stop sign", "parking meter",
    "bird", "cat", "dog", "horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe",
    "skis", "snowboard", "kite", "surfboard", "frisbee",
})


def reject_irrelevant(detections: Iterable[Detection],
                      irrelevant: Iterable[str] = IRRELEVANT_CLASSES) -> list[Detection]:
    """Drop detections whose best label is irrelevant; strip irrelevant alternatives from the
    others (a box that is most likely a person must not survive as its second guess)."""
    banned = set(irrelevant)
    kept = []
    for d in detections:
        if not d.labels or d.labels[0] in banned:
            continue
        pairs = [(label, score) for label, score in zip(d.labels, d.scores) if label not in banned]
        kept.append(Detection(d.box, [p[0] for p in pairs], [p[1] for p in pairs], d.full_frame))
    return kept
