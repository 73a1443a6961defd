"""Whole-sequence fusion: the detections of every detected frame -> 3-D object hypotheses.

A detection lifted to 3-D (`Sighting`: the box's 3-D attributes in one frame) joins the
hypothesis it most plausibly shows, frame by frame in sequence order, so an object is not
forgotten between keyframe groups:

- feasible when the labels are compatible (`labels_compatible`) and the 3-D box centre lies
  within the gate max(ASSOC_MAX_DISTANCE, ASSOC_EXTENT_FRACTION * extent) of the hypothesis'
  centre (the larger extent of the two for the same best label, else the smaller), or - for the same best label - the two 3-D boxes
  overlap (intersection / smaller volume >= PART_OVERLAP: a big object seen in parts);
- within one frame the detections are paired one-to-one with hypotheses (Hungarian method on
  distance / gate + a label-mismatch cost), so two objects seen side by side never share one.

After the pass, hypotheses with the same best label that were never detected in the same frame
and whose boxes share APART_OVERLAP of the smaller or whose centres fall within the gate are
folded together (`consolidate`):
association is greedy in time, this undoes the splits it makes when a part view comes first.
Parts seen on their own fold into their object too: a chair's back and base boxed in different
tiles (two chairs cannot share floor space), a TV's corner a tile called "book".

Each hypothesis accumulates label evidence over all its sightings (`fuse_labels`:
the label the detector repeats wins over one it said once with a high score), its position
Gaussian (pooled Eq. 8 moments), a robust union box, the summed HSV histogram, the colour voted
over the views that see it well (and a second colour) and the best-scored view's thumbnail.
"""
from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Iterable, Optional, Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from sg3d.core.geometry import FLOOR_STANDING_LABELS
from sg3d.core.model import TOP_K, ObjectObservation, vec3
from sg3d.ingest.detect.models import Detection
from sg3d.ingest.objects.attributes import ObjectAttributes
from sg3d.ingest.objects.colour import ColourReading, vote
from sg3d.ingest.objects.moments import combine_gaussians

ASSOC_MAX_DISTANCE = 0.25
ASSOC_EXTENT_FRACTION = 0.5
LABEL_MISMATCH_COST = 0.5
# Two boxes overlapping this much of the smaller one are parts of one object.
PART_OVERLAP = 0.5
# Two same-label hypotheses never detected in one frame whose boxes share this much of the
# smaller one are one object: two solid things of one kind cannot share a quarter of the space,
# and two that stand that close are seen together.
APART_OVERLAP = 0.25
# Two hypotheses seen together in at most this share of the smaller one's frames may still be
# one object (a frame that boxed it twice, e.g. a whole table and one of its ends).
MAX_SHARED_FRAMES = 0.1
# Same-label hypotheses whose boxes nest this deeply are one object even when seen together.
NESTED_OVERLAP = 0.7
# A hypothesis' box: per-axis percentiles of its sightings' lower and upper bounds. A part seen
# in a fifth of the views still widens the box; a single flying-pixel box does not.
BOX_LOW_PERCENTILE = 20.0
BOX_HIGH_PERCENTILE = 80.0
# The fused object's box (what relations and answers use) reaches, on each side of each
# horizontal axis, as far as at least BOX_SUPPORT sightings (or BOX_SUPPORT_FRACTION of them, if
# more) reach: the far end of a table seen in a few views of a hundred still belongs to it.
# Heights keep the percentile box (what stands on a table inflates its boxes upwards), and so
# does association (a core that rare part views do not drag around).
BOX_SUPPORT = 3
BOX_SUPPORT_FRACTION = 0.05
# Only objects this wide (core box, horizontally) are seen in parts; a smaller one is seen whole in
# each view, so its outermost boxes are noise (a mug's box that took in the magazine beside it).
PART_VIEW_MIN_EXTENT = 0.5
_INFEASIBLE = 1e6


def object_box(h: "Hypothesis") -> tuple[np.ndarray, np.ndarray]:
    """The fused object's box (gravity frame). For an object whose core box is at least
    PART_VIEW_MIN_EXTENT wide: along e1 and e2 the k-th lowest lower bound and the k-th highest
    upper bound of its sightings' boxes, k = max(BOX_SUPPORT, BOX_SUPPORT_FRACTION * n) capped at
    n (the box reaches as far as k sightings agree it does), along up the hypothesis' percentile
    box. A smaller object keeps the percentile box."""
    if max(h.hi[0] - h.lo[0], h.hi[1] - h.lo[1]) < PART_VIEW_MIN_EXTENT:
        return h.lo.copy(), h.hi.copy()
    lows = np.array([s.lo for s in h.sightings])
    highs = np.array([s.hi for s in h.sightings])
    n = len(lows)
    k = min(n, max(BOX_SUPPORT, int(np.ceil(BOX_SUPPORT_FRACTION * n))))
    lo, hi = np.sort(lows, axis=0)[k - 1], np.sort(highs, axis=0)[n - k]
    lo[2], hi[2] = h.lo[2], h.hi[2]
    return lo, hi


def fuse_labels(members: Sequence, top_k: int = TOP_K) -> tuple[list[str], list[float]]:
    """Top-k labels of a hypothesis: each label's score averaged over ALL its detections (members
    with a `.detection`), a detection that did not list the label counting 0, so a label the
    detector repeats beats one it said once with a high score."""
    if not members:
        return [], []
    total: dict[str, float] = defaultdict(float)
    for m in members:
        for label, score in zip(m.detection.labels, m.detection.scores):
            total[label] += float(score)
    ranked = sorted(total.items(), key=lambda kv: (-kv[1], kv[0]))[:top_k]
    return [label for label, _ in ranked], [s / len(members) for _, s in ranked]


@dataclass
class Sighting:
    """One detection with its 3-D attributes in one frame; `lo`/`hi` bound its 3-D box in
    gravity-frame coordinates (along e1, e2, up of `horizontal_basis`)."""

    frame: int
    detection: Detection
    attrs: ObjectAttributes
    lo: np.ndarray
    hi: np.ndarray

    @classmethod
    def of(cls, frame: int, detection: Detection, attrs: ObjectAttributes, basis: np.ndarray) -> "Sighting":
        centre = basis @ np.asarray(attrs.centre, dtype=np.float64)
        half = np.asarray(attrs.size, dtype=np.float64) / 2
        return cls(frame, detection, attrs, centre - half, centre + half)

    @property
    def extent(self) -> float:
        return float(max(self.attrs.size))

    def moved(self, motion: np.ndarray, basis: np.ndarray) -> "Sighting":
        """The sighting as a camera moved by the rigid world motion `motion` (4x4) saw it: its
        centres moved, its size and spread kept (loop closure corrects a pose by centimetres and
        a degree or two, so the box's axes in the gravity frame stay as measured)."""
        R, t = motion[:3, :3], motion[:3, 3]
        mx, my, mz = (float(x) for x in R @ np.asarray(self.attrs.mean, float) + t)
        cx, cy, cz = (float(x) for x in R @ np.asarray(self.attrs.centre, float) + t)
        mean, centre = (mx, my, mz), (cx, cy, cz)
        return Sighting.of(self.frame, self.detection, replace(self.attrs, mean=mean, centre=centre), basis)


def box_overlap(lo_a: Any, hi_a: Any, lo_b: Any, hi_b: Any) -> float:
    """Intersection volume of two axis-aligned boxes over the smaller one's volume, in [0, 1]
    (degenerate sizes get a 1 cm floor so flat objects can still overlap)."""
    inter = np.clip(np.minimum(hi_a, hi_b) - np.maximum(lo_a, lo_b), 0.0, None)
    va = np.prod(np.maximum(np.asarray(hi_a) - lo_a, 0.01))
    vb = np.prod(np.maximum(np.asarray(hi_b) - lo_b, 0.01))
    return float(np.prod(np.maximum(inter, 0.0)) / min(va, vb)) if inter.all() else 0.0


@dataclass
class Hypothesis:
    """A 3-D object candidate: every sighting that was associated with it."""

    hid: int
    sightings: list[Sighting] = field(default_factory=list)

    def add(self, s: Sighting) -> None:
        self.sightings.append(s)
        self.__dict__.pop("_summary", None)

    @cached_property
    def _summary(self) -> dict:
        lows = np.array([s.lo for s in self.sightings])
        highs = np.array([s.hi for s in self.sightings])
        labels, scores = fuse_labels(self.sightings)
        return {
            "frames": sorted({s.frame for s in self.sightings}),
            "centre_gravity": np.median((lows + highs) / 2, axis=0),
            "lo": np.percentile(lows, BOX_LOW_PERCENTILE, axis=0),
            "hi": np.percentile(highs, BOX_HIGH_PERCENTILE, axis=0),
            "labels": labels, "scores": scores,
            "candidates": {label for s in self.sightings for label in s.detection.labels},
        }

    @property
    def frames(self) -> list[int]:
        return self._summary["frames"]

    @property
    def n_frames(self) -> int:
        return len(self.frames)

    @property
    def lo(self) -> np.ndarray:
        return self._summary["lo"]

    @property
    def hi(self) -> np.ndarray:
        return self._summary["hi"]

    @property
    def centre_gravity(self) -> np.ndarray:
        return self._summary["centre_gravity"]

    @property
    def extent(self) -> float:
        return float(np.max(self.hi - self.lo))

    @property
    def labels(self) -> list[str]:
        return self._summary["labels"]

    @property
    def scores(self) -> list[float]:
        return self._summary["scores"]

    @property
    def label(self) -> str:
        return self.labels[0]

    @property
    def candidate_labels(self) -> set[str]:
        return self._summary["candidates"]


def labels_compatible(detection: Detection, h: Hypothesis) -> bool:
    """The same best label, or each side's best label among the other's candidates (a chair
    the detector once calls "bench" still joins; a vase beside it does not become the chair)."""
    return detection.label == h.label or (detection.label in h.candidate_labels and h.label in detection.labels)


def association_cost(s: Sighting, h: Hypothesis) -> float:
    """distance / gate + LABEL_MISMATCH_COST when the labels differ; _INFEASIBLE outside the
    gate (unless same-label boxes overlap by PART_OVERLAP) or for incompatible labels."""
    if not labels_compatible(s.detection, h):
        return _INFEASIBLE
    same_label = s.detection.label == h.label
    # a big object's parts lie far apart; a differently named thing must be close to join
    extent = max(s.extent, h.extent) if same_label else min(s.extent, h.extent)
    gate = max(ASSOC_MAX_DISTANCE, ASSOC_EXTENT_FRACTION * extent)
    centre = (s.lo + s.hi) / 2
    distance = float(np.linalg.norm(centre - h.centre_gravity))
    if distance > gate:
        if not (same_label and box_overlap(s.lo, s.hi, h.lo, h.hi) >= PART_OVERLAP):
            return _INFEASIBLE
        distance = gate
    return distance / gate + (0.0 if same_label else LABEL_MISMATCH_COST)


def suppress_duplicates(frame_sightings: Sequence[Sighting]) -> list[Sighting]:
    """3-D non-maximum suppression within one frame: of two sightings with compatible labels
    whose 3-D boxes overlap by PART_OVERLAP of the smaller one, keep the higher-scored (the
    detector boxed one object twice: a whole table and one end, a mug and its handle)."""
    kept: list[Sighting] = []
    for s in sorted(frame_sightings, key=lambda s: -s.detection.score):
        if not any((s.detection.label in k.detection.labels or k.detection.label in s.detection.labels)
                   and box_overlap(s.lo, s.hi, k.lo, k.hi) >= PART_OVERLAP for k in kept):
            kept.append(s)
    return kept


def associate(sightings: Iterable[Sighting]) -> list[Hypothesis]:
    """Sightings (any order) -> hypotheses, frame by frame in index order, one-to-one per frame
    (after `suppress_duplicates` within the frame)."""
    by_frame: dict[int, list[Sighting]] = {}
    for s in sightings:
        by_frame.setdefault(s.frame, []).append(s)
    by_frame = {f: suppress_duplicates(v) for f, v in by_frame.items()}
    hyps: list[Hypothesis] = []
    for frame in sorted(by_frame):
        dets = by_frame[frame]
        matched: set[int] = set()
        if hyps:
            cost = np.array([[association_cost(s, h) for h in hyps] for s in dets])
            rows, cols = linear_sum_assignment(cost)
            for r, c in zip(rows, cols):
                if cost[r, c] < _INFEASIBLE:
                    hyps[c].add(dets[r])
                    matched.add(r)
        for r, s in enumerate(dets):
            if r not in matched:
                hyps.append(Hypothesis(len(hyps), [s]))
    return hyps


def _seen_apart(a: Hypothesis, b: Hypothesis) -> bool:
    return len(set(a.frames) & set(b.frames)) <= MAX_SHARED_FRAMES * min(a.n_frames, b.n_frames)


def part_read_as_other(part: Hypothesis, whole: Hypothesis) -> bool:
    """A part of `whole` named otherwise in views that did not show the whole (a tile sees a
    corner of a TV and says "book", listing "tv" second): `part`'s box lies inside `whole`'s
    (NESTED_OVERLAP of the smaller, and it is the smaller), `whole`'s label is among `part`'s
    candidate labels, and the two were hardly ever detected in one frame."""
    return (np.prod(part.hi - part.lo) <= np.prod(whole.hi - whole.lo)
            and whole.label in part.candidate_labels
            and box_overlap(part.lo, part.hi, whole.lo, whole.hi) >= NESTED_OVERLAP
            and _seen_apart(part, whole))


def share_floor_space(a: Hypothesis, b: Hypothesis) -> bool:
    """Two pieces of floor-standing furniture of one kind (FLOOR_STANDING_LABELS) whose
    footprints nest (NESTED_OVERLAP of the smaller) are one piece: two chairs cannot stand in one
    place, so boxes of a chair's back and of its base seen in different tiles are one chair."""
    return (a.label == b.label and a.label in FLOOR_STANDING_LABELS
            and box_overlap(a.lo[:2], a.hi[:2], b.lo[:2], b.hi[:2]) >= NESTED_OVERLAP)


def _may_fold(a: Hypothesis, b: Hypothesis) -> bool:
    if a.label != b.label:
        return part_read_as_other(a, b) or part_read_as_other(b, a)
    if box_overlap(a.lo, a.hi, b.lo, b.hi) >= NESTED_OVERLAP or share_floor_space(a, b):
        return True            # one inside the other: a part boxed on its own (a chair's seat)
    if not _seen_apart(a, b):
        return False
    gate = max(ASSOC_MAX_DISTANCE, ASSOC_EXTENT_FRACTION * max(a.extent, b.extent))
    if float(np.linalg.norm(a.centre_gravity - b.centre_gravity)) <= gate:
        return True
    return box_overlap(a.lo, a.hi, b.lo, b.hi) >= APART_OVERLAP


def consolidate(hyps: Sequence[Hypothesis]) -> list[Hypothesis]:
    """Fold same-label hypotheses that nest, share floor space (`share_floor_space`), or were
    never detected together and overlap (APART_OVERLAP) or lie within the association gate, and parts read as
    another label (`part_read_as_other`), the closest pairs first, until none is left; ids are
    renumbered."""
    pool = [Hypothesis(h.hid, list(h.sightings)) for h in hyps]
    while True:
        best: Optional[tuple[float, int, int]] = None
        for i in range(len(pool)):
            for j in range(i + 1, len(pool)):
                if _may_fold(pool[i], pool[j]):
                    d = float(np.linalg.norm(pool[i].centre_gravity - pool[j].centre_gravity))
                    if best is None or d < best[0]:
                        best = (d, i, j)
        if best is None:
            break
        _, i, j = best
        for s in pool[j].sightings:
            pool[i].add(s)
        del pool[j]
    ordered = sorted(pool, key=lambda h: (h.frames[0], h.hid))
    return [Hypothesis(k, sorted(h.sightings, key=lambda s: s.frame)) for k, h in enumerate(ordered)]


def fuse(local_id: str, h: Hypothesis, basis: np.ndarray, labels: Optional[Sequence[str]] = None,
         scores: Optional[Sequence[float]] = None) -> ObjectObservation:
    """One object from all the sightings of a hypothesis: pooled position Gaussian (Eq. 8
    moments), the robust union box, summed histogram (Eq. 9 counts), the colour and second colour
    voted over the views weighted by how well they see it (`sg3d.ingest.objects.colour.vote`), accumulated
    label evidence (or the given `labels`/`scores`) and the best-scored view's thumbnail."""
    first = h.sightings[0].attrs
    mean, var, n = np.asarray(first.mean, float), np.asarray(first.var, float), first.n_points
    for s in h.sightings[1:]:
        mean, var, n = combine_gaussians(mean, var, n, s.attrs.mean, s.attrs.var, s.attrs.n_points)
    best = max(h.sightings, key=lambda s: s.detection.score)
    colour, colour2, _ = vote([s.attrs.colour_reading or ColourReading.single(s.attrs.colour) for s in h.sightings],
                              [s.attrs.view_weight for s in h.sightings])
    lo, hi = object_box(h)
    centre = basis.T @ ((lo + hi) / 2)
    return ObjectObservation(
        local_id=local_id, labels=list(labels if labels is not None else h.labels),
        scores=[float(v) for v in (scores if scores is not None else h.scores)],
        mean=vec3(mean), var=vec3(var), n_points=int(n),
        size=vec3(hi - lo), box_centre=vec3(centre),
        hist=np.sum([s.attrs.hist for s in h.sightings], axis=0),
        colour=colour, colour2=colour2, thumbnail=best.attrs.thumbnail,
        first_frame=h.frames[0], last_frame=h.frames[-1], n_frames=h.n_frames)
