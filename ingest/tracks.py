"""Detections of one keyframe group associated across its frames by 3-D position.

Each `Track` is one object candidate with the frames it was seen in; SDR keeps the tracks seen
often enough (`ingest.sdr.reject_rare_tracks`) and the pipeline fuses a track into one
`ObjectObservation` (labels via `fuse_labels`).
"""
from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from itertools import count
from typing import Any, Iterable, Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from ingest.detect import Detection
from ingest.model import TOP_K

# Frames of one keyframe group overlap strongly (KGE), so the same small object's 3-D mean
# moves only by depth noise and the changing visible part: a few cm to ~20 cm.
ASSOC_MAX_DISTANCE = 0.25
# Big objects (tables, counters) show different parts from frame to frame, so their mean
# moves by a fraction of their size; the gate grows with the object.
ASSOC_EXTENT_FRACTION = 0.5
# A different top label costs this much of the gate: same-label matches win ties, but a
# chair that one frame calls "bench" still joins its track when its labels overlap.
LABEL_MISMATCH_COST = 0.5
_INFEASIBLE = 1e6


@dataclass
class FrameDetection:
    """A detection lifted to 3-D: `position` in world metres (e.g. the Eq. 8 mean), `extent`
    the object's largest size in metres (0 when unknown); `payload` is carried untouched."""

    frame: int
    detection: Detection
    position: tuple[float, float, float]
    extent: float = 0.0
    payload: Any = None


@dataclass
class Track:
    """One object candidate: its detections, at most one per frame."""

    track_id: int
    members: list[FrameDetection] = field(default_factory=list)

    @property
    def frames(self) -> list[int]:
        return sorted({m.frame for m in self.members})

    @property
    def n_frames(self) -> int:
        return len(self.frames)

    @property
    def position(self) -> np.ndarray:
        return np.mean([np.asarray(m.position, dtype=np.float64) for m in self.members], axis=0)

    @property
    def extent(self) -> float:
        return max(float(m.extent) for m in self.members)

    @property
    def candidate_labels(self) -> set[str]:
        return {label for m in self.members for label in m.detection.labels}

    @property
    def labels(self) -> list[str]:
        return fuse_labels(self.members)[0]

    @property
    def scores(self) -> list[float]:
        return fuse_labels(self.members)[1]

    @property
    def label(self) -> str:
        return self.labels[0]


def fuse_labels(members: Sequence[FrameDetection], top_k: int = TOP_K) -> tuple[list[str], list[float]]:
    """Top-k labels of a track: each label's score averaged over ALL the track's detections,
    a detection that did not list the label counting 0, so a label the detector repeats beats
    one it said once with a high score."""
    if not members:
        return [], []
    total: dict[str, float] = defaultdict(float)
    for m in members:
        for label, score in zip(m.detection.labels, m.detection.scores):
            total[label] += float(score)
    ranked = sorted(total.items(), key=lambda kv: (-kv[1], kv[0]))[:top_k]
    return [label for label, _ in ranked], [s / len(members) for _, s in ranked]


def labels_compatible(detection: Detection, track: Track) -> bool:
    """The detection's best label is among the track's candidates, or the track's best label
    is among the detection's."""
    return detection.label in track.candidate_labels or track.label in detection.labels


def _cost(det: FrameDetection, track: Track, max_distance: float, extent_fraction: float) -> float:
    gate = max(max_distance, extent_fraction * max(det.extent, track.extent))
    distance = float(np.linalg.norm(np.asarray(det.position, dtype=np.float64) - track.position))
    if distance > gate or not labels_compatible(det.detection, track):
        return _INFEASIBLE
    mismatch = 0.0 if det.detection.label == track.label else LABEL_MISMATCH_COST
    return distance / gate + mismatch


def associate(
    detections: Iterable[FrameDetection],
    max_distance: float = ASSOC_MAX_DISTANCE,
    extent_fraction: float = ASSOC_EXTENT_FRACTION,
) -> list[Track]:
    """Group the detections of one keyframe group into tracks, frame by frame in index order.

    Each frame's detections are matched one-to-one to the existing tracks (Hungarian method on
    distance / gate + label mismatch), so two objects seen together in a frame never share a
    track; a detection beyond every gate or with incompatible labels starts a new track.
    """
    by_frame: dict[int, list[FrameDetection]] = defaultdict(list)
    for d in detections:
        by_frame[d.frame].append(d)
    tracks: list[Track] = []
    ids = count()
    for frame in sorted(by_frame):
        dets = by_frame[frame]
        matched: set[int] = set()
        if tracks:
            cost = np.array([[_cost(d, t, max_distance, extent_fraction) for t in tracks] for d in dets])
            rows, cols = linear_sum_assignment(cost)
            for r, c in zip(rows, cols):
                if cost[r, c] < _INFEASIBLE:
                    tracks[c].members.append(dets[r])
                    matched.add(r)
        for r, d in enumerate(dets):
            if r not in matched:
                tracks.append(Track(next(ids), [d]))
    return tracks
