"""Keyframe groups -> local 3-D scene graphs (paper Sec. III, IV-C, V-B).

Per keyframe group: detect objects in each of its frames, drop irrelevant classes (SDR), lift
each box to 3-D attributes, associate the detections of the group's frames into tracks, drop
tracks seen in too few frames (SDR), fuse each track into one object, compute the relations of
every frame from 3-D geometry, vote them across the frames and filter them by the relation
prior (SDR, Eq. 7). The result is one `LocalGraph` per group, ready to merge.

The ablation presets of the paper's Table I switch modules on and off (`METHODS`).
"""
from __future__ import annotations

import hashlib
import time
from collections import Counter, defaultdict
from dataclasses import dataclass, field
from typing import Iterator, Optional

import numpy as np

from ingest.abir import ABIR
from ingest.attributes import ObjectAttributes, measure_object
from ingest.detect import Detection, Detector
from ingest.frames import Frame, FrameError
from ingest.kge import KeyframeGroup, KeyframeGrouper
from ingest.model import LocalGraph, ObjectObservation, RelationObservation
from ingest.moments import combine_gaussians
from ingest.relations import ObjectGeometry, spatial_relations
from ingest.sdr import (MIN_FRAMES, filter_relations, reject_irrelevant, reject_rare_tracks,
                        vote_relations)
from ingest.selection import FrameSelector
from ingest.tracks import FrameDetection, Track, associate


@dataclass(frozen=True)
class Method:
    """Which modules run (paper Table I)."""

    name: str
    efficient: bool      # ABIR + KGE: only sharp, non-redundant frames are processed
    three_d: bool        # 3-D attributes + same-node detection (else a 2-D graph per frame)
    sdr: bool            # spurious detection rejection


METHODS = {
    "2d-basic": Method("2d-basic", efficient=False, three_d=False, sdr=False),
    "2d-efficient": Method("2d-efficient", efficient=True, three_d=False, sdr=False),
    "3d-basic": Method("3d-basic", efficient=False, three_d=True, sdr=False),
    "3d-efficient": Method("3d-efficient", efficient=True, three_d=True, sdr=False),
    "3d-full": Method("3d-full", efficient=True, three_d=True, sdr=True),
}


@dataclass
class PipelineStats:
    groups: int = 0
    frames_detected: int = 0
    detections: int = 0
    objects: int = 0
    relations: int = 0
    seconds: dict = field(default_factory=lambda: defaultdict(float))


@dataclass
class _Seen:
    """One detection with its 3-D attributes in one frame."""

    frame: Frame
    detection: Detection
    attrs: ObjectAttributes


def _frame_detections(frame: Frame, detector: Detector, up, method: Method,
                      stats: PipelineStats) -> list[_Seen]:
    t0 = time.perf_counter()
    dets = detector.detect(frame.color)
    stats.seconds["detect"] += time.perf_counter() - t0
    stats.frames_detected += 1
    if method.sdr:
        dets = reject_irrelevant(dets)
    t0 = time.perf_counter()
    seen = []
    for det in dets:
        attrs = measure_object(frame, det.box, up)
        if attrs is not None:
            seen.append(_Seen(frame, det, attrs))
    stats.seconds["attributes"] += time.perf_counter() - t0
    stats.detections += len(seen)
    return seen


def fuse_track(local_id: str, track: Track) -> ObjectObservation:
    """One object from the frames of a track: pooled Gaussian, summed histogram, median size,
    the best-scored view's thumbnail and the most frequent colour name."""
    members: list[_Seen] = [m.payload for m in track.members]
    mean, var, n = np.asarray(members[0].attrs.mean, float), np.asarray(members[0].attrs.var, float), members[0].attrs.n_points
    for m in members[1:]:
        mean, var, n = combine_gaussians(mean, var, n, m.attrs.mean, m.attrs.var, m.attrs.n_points)
    best = max(members, key=lambda m: m.detection.score)
    frames = [m.frame.index for m in members]
    colours = Counter(m.attrs.colour for m in members)
    return ObjectObservation(
        local_id=local_id, labels=track.labels, scores=[float(s) for s in track.scores],
        mean=tuple(float(v) for v in mean), var=tuple(float(v) for v in var), n_points=int(n),
        size=tuple(float(v) for v in np.median([m.attrs.size for m in members], axis=0)),
        box_centre=tuple(float(v) for v in np.median([m.attrs.centre for m in members], axis=0)),
        hist=np.sum([m.attrs.hist for m in members], axis=0),
        colour=colours.most_common(1)[0][0], thumbnail=best.attrs.thumbnail,
        first_frame=min(frames), last_frame=max(frames), n_frames=len(set(frames)))


def _frame_relations(tracks: dict[str, Track], frame: Frame, up) -> list[RelationObservation]:
    geoms = []
    for local_id, track in tracks.items():
        for m in track.members:
            if m.frame == frame.index:
                seen: _Seen = m.payload
                geoms.append(ObjectGeometry(local_id, track.label, seen.attrs.centre, seen.attrs.size))
    return spatial_relations(geoms, up, camera_pose=frame.pose) if len(geoms) > 1 else []


def _dedupe(relations: list[RelationObservation]) -> list[RelationObservation]:
    best: dict[tuple, RelationObservation] = {}
    for r in relations:
        key = (r.subject, r.predicate, r.object)
        if key not in best or r.score > best[key].score:
            best[key] = r
    return list(best.values())


def local_graph(group: KeyframeGroup, detector: Detector, up, method: Method, room: str,
                building: str, key: Optional[str], stats: PipelineStats) -> LocalGraph:
    """The local 3-D scene graph of one keyframe group."""
    seen = [s for frame in group.frames for s in _frame_detections(frame, detector, up, method, stats)]
    t0 = time.perf_counter()
    # the box centre, not the centre patch: a big object seen in parts keeps one track
    fds = [FrameDetection(s.frame.index, s.detection, s.attrs.centre, float(max(s.attrs.size)), s) for s in seen]
    if method.three_d:
        tracks = associate(fds)
    else:  # a 2-D graph: every detection of every frame is its own node
        tracks = [Track(i, [fd]) for i, fd in enumerate(fds)]
    if method.sdr:
        # a one-frame group cannot show an object twice; ask for what the group can give
        tracks = reject_rare_tracks(tracks, min_frames=min(MIN_FRAMES, len(group.frames)))
    by_id = {f"t{t.track_id}": t for t in tracks}
    objects = [fuse_track(local_id, t) for local_id, t in by_id.items()]
    stats.seconds["tracks"] += time.perf_counter() - t0

    t0 = time.perf_counter()
    per_frame = [_frame_relations(by_id, frame, up) for frame in group.frames]
    if method.sdr:
        relations = vote_relations(per_frame)
        labels = {o.local_id: o.label for o in objects}
        centres = {o.local_id: o.mean for o in objects}
        relations = filter_relations(relations, labels, centres)
    else:
        relations = [r for rels in per_frame for r in rels]
    relations = _dedupe(relations)
    stats.seconds["relations"] += time.perf_counter() - t0
    stats.groups += 1
    stats.objects += len(objects)
    stats.relations += len(relations)
    return LocalGraph(room=room, building=building, objects=objects, relations=relations, key=key,
                      frames=[f.index for f in group.frames], up=tuple(float(v) for v in up))


def single_frame_groups(seq, start: int, stop: Optional[int], selector_stats) -> Iterator[KeyframeGroup]:
    """Without ABIR and KGE (the basic presets) every readable frame is a group of its own."""
    stop = len(seq) if stop is None else min(stop, len(seq))
    selector_stats.frames += len(range(start, stop))
    t0 = time.perf_counter()
    skipped_before = len(seq.skipped)
    index = 0
    for frame in seq.frames(start, stop, lazy=True):
        try:
            frame.load()
        except FrameError:  # counted in seq.skipped by the reader
            continue
        selector_stats.read += 1
        selector_stats.keyframes += 1
        selector_stats.groups += 1
        selector_stats.seconds = time.perf_counter() - t0
        yield KeyframeGroup(index, [frame])
        index += 1
    selector_stats.skipped += len(seq.skipped) - skipped_before
    selector_stats.seconds = time.perf_counter() - t0


def run_key(seq_path: str, n_frames: int, method: Method, room: str, building: str) -> str:
    """Identifies one build so its merges can be recognised on a re-run or --resume."""
    text = f"{seq_path}|{n_frames}|{method.name}|{building}/{room}"
    return hashlib.sha1(text.encode()).hexdigest()[:12]


def make_selector(abir_gain: Optional[float] = None, t_key: float = 0.2,
                  t_anchor: float = 0.68) -> FrameSelector:
    abir = ABIR() if abir_gain is None else ABIR(gain=abir_gain)
    return FrameSelector(abir, KeyframeGrouper(t_key=t_key, t_anchor=t_anchor))
