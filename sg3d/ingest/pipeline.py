"""A posed RGB-D sequence -> local 3-D scene graphs, one per chunk of frames (paper Sec. III-V).

Per chunk [a, b) of the sequence (a whole room is one chunk by default):
1. frame selection: ABIR drops blurry frames, KGE (Algorithm 1) picks keyframes and anchors,
   `sg3d.ingest.select.coverage` adds the sharp frames with the most new viewpoints up to a frame budget,
   and each chosen frame is replaced by the sharpest frame of its short window of the recording
   (so a sub-degree pose change, which moves a choice by a frame or two, keeps the same frames);
2. detection on the chosen frames, irrelevant classes dropped (SDR), every box lifted to 3-D;
3. fusion of the detections of ALL chosen frames into object hypotheses (`sg3d.ingest.objects.fusion`);
4. existence from multi-view evidence, negative evidence included (`sg3d.ingest.objects.existence`): the
   paper's "seen at least twice" rule, plus "seen in a fair share of the views that show it";
5. relations of every chosen frame from 3-D geometry, voted across the frames, completed by
   the relations of the fused whole-sequence boxes (`sdr.with_whole_geometry`) and filtered by
   the relation prior (SDR, Eq. 7).
The result of a chunk is one `LocalGraph`, merged by `sg3d.graphdb.merge` (Eq. 10-15). Chunks, frame
choice and fusion depend only on the sequence and the settings, so a re-run or `--resume` skips
exactly the chunks already merged and ends with the graph a clean build gives.

The ablation presets of the paper's Table I switch modules on and off (`sg3d.ingest.config.METHODS`);
each stage is a function of `sg3d.ingest.stages` returning a frozen result with its counts and
seconds, and `BuildPipeline` runs them over a chunk.
"""
from __future__ import annotations

import hashlib
import threading
from collections import Counter, defaultdict
from dataclasses import dataclass, field, fields
from typing import Any, Optional, Sequence

from sg3d.core.model import KnownObject, LocalGraph, ScanInfo, vec3
from sg3d.ingest.config import BuildConfig
from sg3d.ingest.detect.models import Detection, Detector
from sg3d.ingest.objects import fusion
from sg3d.ingest.readers.frames import Frame, FrameError
from sg3d.ingest.stages import (
    ColourFn,
    DiscoverFn,
    Evidence,
    Ground,
    ProgressFn,
    R,
    at_fixed_precision,
    detect_frames,
    depth_discovery,
    discover_objects,
    frame_boxes,
    fuse_objects,
    lifted,
    relate,
    rescanned,
    select_frames,
)

# the name the front ends and tests know the build's config by
Settings = BuildConfig


@dataclass
class PipelineStats:
    """A build's counts and seconds: the sum of its stages' results (`add`)."""

    chunks: int = 0
    frames: int = 0              # frames in the range asked for
    read: int = 0                # frames that reached ABIR with a readable image
    blurry: int = 0
    keyframes: int = 0
    anchors: int = 0
    coverage: int = 0            # extra frames chosen for new viewpoints
    detected: int = 0            # frames the detector ran on
    detections: int = 0          # detections lifted to 3-D
    hypotheses: int = 0
    kept: int = 0
    rejected: Counter = field(default_factory=Counter)   # reason -> hypotheses
    objects: int = 0
    unnamed: int = 0             # objects found from depth that no detector named
    structure: int = 0           # floor, walls and surfaces
    relations: int = 0
    seconds: dict = field(default_factory=lambda: defaultdict(float))

    def add(self, result: R) -> R:
        """Count a stage's result in (its counts and seconds); the result, returned."""
        for name, value in result.counts().items():
            setattr(self, name, getattr(self, name) + value)
        for phase, s in result.seconds.items():
            self.seconds[phase] += s
        return result

    def as_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in ("seconds", "rejected")}
        d["rejected"] = dict(sorted(self.rejected.items()))
        return d


def run_key(seq_path: str, n_frames: int, settings: BuildConfig, room: str, building: str) -> str:
    """Identifies one build (sequence, settings, room) so its merges are recognised on a re-run
    or --resume; a change of any setting that changes the graph is a different build."""
    text = f"{seq_path}|{n_frames}|{settings.fingerprint()}|{building}/{room}"
    return hashlib.sha1(text.encode()).hexdigest()[:12]


def chunk_ranges(start: int, stop: int, chunk_frames: int) -> list[tuple[int, int]]:
    """[start, stop) cut into consecutive ranges of chunk_frames (the last one shorter)."""
    if stop <= start:
        return []
    step = max(1, int(chunk_frames))
    return [(a, min(a + step, stop)) for a in range(start, stop, step)]


def _prepare_in_background(detector: Detector) -> threading.Thread:
    """Load the detector's network on a thread while frames are selected (a failure to load is
    raised by the first detection, where it was raised before)."""
    def prepare() -> None:
        try:
            getattr(detector, "prepare", lambda: None)()
        except Exception:   # noqa: BLE001 - re-raised by detect() on the build's own thread
            pass
    thread = threading.Thread(target=prepare, name="sg3d-detector-load", daemon=True)
    thread.start()
    return thread


def detections_of(frame: Frame, detector: Detector, settings: BuildConfig, stats: PipelineStats) -> list[Detection]:
    """The detector's boxes on one decoded frame, irrelevant classes dropped under SDR, counted into `stats`."""
    return stats.add(frame_boxes(frame, detector, settings.method.sdr)).boxes


def sightings_of(frame: Frame, dets: list[Detection], ground: Ground, stats: PipelineStats) -> list[fusion.Sighting]:
    """A frame's detections lifted to 3-D with their attributes (`sg3d.ingest.stages.lifted`),
    timed into `stats`."""
    return stats.add(lifted(frame, dets, ground)).sightings


def sequence_colour(seq: Any) -> ColourFn:
    """Frame index -> its colour image read again from `seq` (None when it cannot be read): the
    colour file only, its depth left undecoded (discovery reads colour again for tens of views)."""
    def colour(index: int) -> Any:
        try:
            return seq.frame(index, lazy=True).color
        except FrameError:
            return None
    return colour


@dataclass(frozen=True)
class Target:
    """Where a local graph goes: its room and building, its merge key (None: always merged), the
    scan it belongs to, and the room's objects as they stand (a re-scan tests their places)."""

    room: str
    building: str = "default"
    key: Optional[str] = None
    scan: Optional[ScanInfo] = None
    known: Sequence[KnownObject] = ()


def graph_of_evidence(evidence: Evidence, target: Target, settings: BuildConfig, stats: PipelineStats,
                      discover: Optional[DiscoverFn] = None) -> LocalGraph:
    """The local graph of what detection saw: `evidence` fused into object hypotheses, kept by
    existence, completed by discovery from depth, related. A build's chunk and a live map's every
    publish both end here, so the same frames give the same graph. `discover` replaces discovery
    from depth (`discover_from_depth`): a live map between two full discoveries carries the last
    one's findings over."""
    method = settings.method
    found = stats.add(fuse_objects(evidence, method, settings))
    objects, by_id = list(found.objects), found.by_id
    if method.sdr and settings.discover.enabled and evidence.views:
        objects += stats.add(discover_objects(evidence, objects, discover or depth_discovery(settings))).objects
        by_id = {k: h for k, h in by_id.items() if k in {o.local_id for o in objects}}   # discovery may drop a misreading
    objects = [at_fixed_precision(o) for o in objects]
    relations = stats.add(relate(by_id, objects, evidence.ground, method, settings)).relations
    empty = stats.add(rescanned(target.known, evidence)).empty_places
    return LocalGraph(room=target.room, building=target.building, objects=objects, relations=relations,
                      key=target.key, frames=[v.index for v in evidence.views], up=vec3(evidence.ground.up),
                      scan=target.scan, empty_places=empty)


class BuildPipeline:
    """The build's stages over one chunk of a sequence: select, detect, then `graph_of_evidence`
    (objects, discover, relate, rescan); `stats` sums every stage's result over the chunks run."""

    def __init__(self, config: BuildConfig, detector: Detector, progress: Optional[ProgressFn] = None) -> None:
        self.config = config
        self.detector = detector
        self.progress = progress
        self.stats = PipelineStats()

    def run(self, seq: Any, span: tuple[int, int], ground: Ground, target: Target) -> LocalGraph:
        """The local 3-D scene graph of frames `span` [a, b) of `seq`."""
        a, b = span
        self.stats.chunks += 1
        self.stats.frames += b - a
        loading = _prepare_in_background(self.detector)
        chosen = self.stats.add(select_frames(seq, span, self.config.method, self.config, self.progress)).frames
        loading.join()
        detected = self.stats.add(detect_frames(seq, chosen, self.detector, ground, self.config.method.sdr,
                                                self.progress))
        evidence = Evidence(detected.sightings, detected.views, sequence_colour(seq), ground)
        return graph_of_evidence(evidence, target, self.config, self.stats)
