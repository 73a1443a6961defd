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

The ablation presets of the paper's Table I switch modules on and off (`METHODS`).
"""
from __future__ import annotations

import functools
import hashlib
import json
import threading
import time
from collections import Counter, defaultdict
from dataclasses import asdict, dataclass, field, fields
from typing import Callable, Optional, Sequence

import numpy as np

from sg3d.core.geometry import METRES_DECIMALS, fixed_precision, horizontal_frame
from sg3d.core.model import (
    KnownObject,
    LocalGraph,
    ObjectObservation,
    RelationObservation,
    ScanInfo,
    vec3,
)
from sg3d.ingest.detect.irrelevant import reject_irrelevant
from sg3d.ingest.detect.models import Detector
from sg3d.ingest.discover import discovery
from sg3d.ingest.objects import existence, fusion, rescan
from sg3d.ingest.objects.attributes import measure_object
from sg3d.ingest.objects.colour import is_screen
from sg3d.ingest.readers.frames import FrameError, decoded_ahead
from sg3d.ingest.relate.relations import (
    ObjectGeometry,
    floor_under_room,
    side_by_side_on_one_support,
    spatial_relations,
)
from sg3d.ingest.relate.sdr import filter_relations, vote_relations, with_whole_geometry
from sg3d.ingest.select import coverage
from sg3d.ingest.select.abir import DEFAULT_GAIN
from sg3d.ingest.select.selection import (
    BUILD_T_ANCHOR,
    SelectionParams,
    choose_detected_frames,
)

# A room-sized sequence is fused whole; longer recordings are cut into chunks of this many
# frames, each fused on its own and merged like the paper's local graphs.
DEFAULT_CHUNK_FRAMES = 3000


@dataclass(frozen=True)
class Method:
    """Which modules run (paper Table I)."""

    name: str
    efficient: bool      # ABIR + KGE (+ coverage): only sharp, informative frames are detected
    three_d: bool        # 3-D fusion + same-node detection (else every detection is a node)
    sdr: bool            # spurious detection rejection (classes, existence, relation vote + prior)


METHODS = {
    "2d-basic": Method("2d-basic", efficient=False, three_d=False, sdr=False),
    "2d-efficient": Method("2d-efficient", efficient=True, three_d=False, sdr=False),
    "3d-basic": Method("3d-basic", efficient=False, three_d=True, sdr=False),
    "3d-efficient": Method("3d-efficient", efficient=True, three_d=True, sdr=False),
    "3d-full": Method("3d-full", efficient=True, three_d=True, sdr=True),
}


@dataclass(frozen=True)
class Settings:
    """Everything that decides which graph a build makes (and so its merge keys)."""

    method: Method = METHODS["3d-full"]
    abir_gain: Optional[float] = None          # None: ABIR's default
    t_key: float = 0.2
    t_anchor: float = BUILD_T_ANCHOR
    detect_fraction: float = coverage.DEFAULT_FRACTION
    min_detect_frames: int = coverage.MIN_FRAMES
    chunk_frames: int = DEFAULT_CHUNK_FRAMES
    detector: str = "ssd-mobilenet-v2-coco"
    score_threshold: float = 0.23
    quality: str = "default"                    # "high": full frame + tiles
    discover: bool = True                       # 3d-full: unnamed objects and structure from depth
    windows: bool = False                       # discovery finds windows too: a walk's (`--rooms auto`)

    @property
    def selection(self) -> SelectionParams:
        """The frame-selection part of these settings."""
        gain = DEFAULT_GAIN if self.abir_gain is None else self.abir_gain
        return SelectionParams(abir_gain=gain, t_key=self.t_key, t_anchor=self.t_anchor,
                               detect_fraction=self.detect_fraction, min_detect_frames=self.min_detect_frames)

    def fingerprint(self) -> str:
        d = asdict(self)
        d["method"] = self.method.name
        if not self.windows:      # the graph of a build without windows is the one it was before they existed
            del d["windows"]
        return json.dumps(d, sort_keys=True)


@dataclass
class PipelineStats:
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

    def as_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in ("seconds", "rejected")}
        d["rejected"] = dict(sorted(self.rejected.items()))
        return d


def run_key(seq_path: str, n_frames: int, settings: Settings, room: str, building: str) -> str:
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


ProgressFn = Callable[[str, int, int], None]   # (phase, done, total)


def select_frames_to_detect(seq, a: int, b: int, settings: Settings, stats: PipelineStats,
                           progress: Optional[ProgressFn]) -> list[int]:
    """Frame indices of [a, b) to run the detector on, in order (every frame when the method is
    not efficient; else `choose_detected_frames`), counted into `stats`."""
    t0 = time.perf_counter()
    if not settings.method.efficient:
        chosen = []
        for frame in seq.frames(a, b, lazy=True):
            chosen.append(frame.index)   # decoded later; a bad image is skipped then
        stats.read += len(chosen)
        stats.seconds["select"] += time.perf_counter() - t0
        return chosen

    def on_frame(frame, decision, role):
        if progress is not None and frame.index % 25 == 0:
            progress("selecting", frame.index - a + 1, b - a)

    choice = choose_detected_frames(seq, a, b, params=settings.selection, on_frame=on_frame)
    st = choice.stats
    stats.read += st.read
    stats.blurry += st.blurry
    stats.keyframes += st.keyframes
    stats.anchors += st.anchors
    stats.coverage += choice.coverage
    stats.seconds["select"] += time.perf_counter() - t0
    return choice.detected


def _prepare_in_background(detector: Detector) -> threading.Thread:
    """Load the detector's network on a thread while frames are selected (a failure to load is
    raised by the first detection, where it was raised before)."""
    def prepare():
        try:
            getattr(detector, "prepare", lambda: None)()
        except Exception:   # noqa: BLE001 - re-raised by detect() on the build's own thread
            pass
    thread = threading.Thread(target=prepare, name="sg3d-detector-load", daemon=True)
    thread.start()
    return thread


def _lazy_frames(seq, chosen: list[int]):
    for i in chosen:
        try:
            yield seq.frame(i, lazy=True)
        except FrameError:
            continue                      # recorded in seq.skipped


def detections_of(frame, detector: Detector, settings: Settings, stats: PipelineStats) -> list:
    """The detector's boxes on one decoded frame, irrelevant classes dropped under SDR."""
    t0 = time.perf_counter()
    dets = detector.detect(frame.color)
    stats.seconds["detect"] += time.perf_counter() - t0
    stats.detected += 1
    return reject_irrelevant(dets) if settings.method.sdr else dets


def sightings_of(frame, dets: list, up, basis, stats: PipelineStats,
                 floor: Optional[float] = None) -> list[fusion.Sighting]:
    """A frame's detections lifted to 3-D with their attributes (boxes without depth drop out),
    measured off the floor at height `floor` when the build knows it (`measure_object`)."""
    t0 = time.perf_counter()
    screens = [det.box for det in dets if is_screen(det.label)]
    sightings = []
    for det in dets:
        attrs = measure_object(frame, det.box, up, det.label, screens, floor)
        if attrs is not None:
            sightings.append(fusion.Sighting.of(frame.index, det, attrs, basis))
    stats.seconds["attributes"] += time.perf_counter() - t0
    return sightings


def detect_frame(frame, detector: Detector, up, basis, settings: Settings,
                 stats: PipelineStats, floor: Optional[float] = None) -> tuple[list[fusion.Sighting], existence.View]:
    """One decoded frame -> its sightings (`detections_of`, `sightings_of`) and its visibility
    view (`existence.View`): what fusion and existence need of a detected frame."""
    sightings = sightings_of(frame, detections_of(frame, detector, settings, stats), up, basis, stats, floor)
    return sightings, existence.View.of(frame)


def _detect(seq, chosen: list[int], detector: Detector, up, basis, settings: Settings,
            stats: PipelineStats, progress: Optional[ProgressFn], floor: Optional[float] = None):
    """Sightings and visibility views of the chosen frames."""
    sightings: list[fusion.Sighting] = []
    views: list[existence.View] = []
    position = {i: n for n, i in enumerate(chosen)}
    # the next frame's images are decoded on a reader thread while this one is detected
    for frame in decoded_ahead(_lazy_frames(seq, chosen), ("color", "depth"), ahead=2):
        n = position[frame.index]
        try:
            frame.load()
        except FrameError:
            continue                      # recorded in seq.skipped
        found, view = detect_frame(frame, detector, up, basis, settings, stats, floor)
        sightings.extend(found)
        views.append(view)
        frame.release()
        if progress is not None:
            progress("detecting", n + 1, len(chosen))
    stats.detections += len(sightings)
    return sightings, views


def _existing(hyps: list[fusion.Hypothesis], views: list[existence.View], basis,
              stats: PipelineStats) -> list[tuple[fusion.Hypothesis, list[str], list[float]]]:
    """SDR's existence test and the size prior over every hypothesis: the kept ones with their
    labels (those the size prior allows); rejections are counted by reason."""
    kept = []
    for h in hyps:
        labels, scores = existence.plausible_labels(h.labels, h.scores, *existence.judged_sizes(h.sightings, h.hi - h.lo))
        if not labels:
            stats.rejected["implausible size for its label"] += 1
            continue
        centre = basis.T @ ((h.lo + h.hi) / 2)
        ev = existence.evidence(centre, h.extent, set(h.frames), views)
        if existence.tile_artefact([s.detection for s in h.sightings]):
            stats.rejected["named only in tiles, though big enough for the full frame"] += 1
        elif ev.detected < existence.MIN_DETECTIONS:
            stats.rejected["seen once"] += 1
        elif not existence.exists(ev):
            stats.rejected["rarely detected where visible"] += 1
        else:
            kept.append((h, labels, scores))
    return kept


def _relations(hyps: dict[str, fusion.Hypothesis], objects: list[ObjectObservation], up,
               method: Method) -> list[RelationObservation]:
    """Relations of every detected frame between the objects it shows, voted (SDR) across frames,
    then completed by the fused objects' own boxes (`with_whole_geometry`)."""
    per_frame: dict[int, list[ObjectGeometry]] = defaultdict(list)
    label_of = {o.local_id: o.label for o in objects}
    for local_id, h in hyps.items():
        best: dict[int, fusion.Sighting] = {}
        for s in h.sightings:   # a folded hypothesis may hold two sightings of one frame
            if s.frame not in best or s.detection.score > best[s.frame].detection.score:
                best[s.frame] = s
        for frame, s in best.items():
            per_frame[frame].append(ObjectGeometry(local_id, label_of[local_id], s.attrs.centre, s.attrs.size))
    frames = [spatial_relations(geoms, up) for _, geoms in sorted(per_frame.items()) if len(geoms) > 1]
    if not method.sdr:
        strongest: dict[tuple, RelationObservation] = {}
        for r in (r for rels in frames for r in rels):
            key = (r.subject, r.predicate, r.object)
            if key not in strongest or r.score > strongest[key].score:
                strongest[key] = r
        return list(strongest.values())
    co_observed: Counter = Counter()
    for geoms in per_frame.values():
        ids = sorted(g.local_id for g in geoms)
        co_observed.update((a, b) for k, a in enumerate(ids) for b in ids[k + 1:])
    voted = vote_relations(frames, co_observed=dict(co_observed))
    things = [o for o in objects if o.layer != "structure"]
    whole = spatial_relations([ObjectGeometry(o.local_id, o.label, _centre(o), o.size) for o in things], up)
    relations = with_whole_geometry(voted, whole)
    labels = {o.local_id: o.label for o in objects}
    centres = {o.local_id: o.mean for o in objects}
    # between objects as ever; then what each stands on of the room's structure
    return (side_by_side_on_one_support(filter_relations(relations, labels, centres))
            + filter_relations(_structure_relations(objects, up), labels, centres))


# (colour_of, views, named objects (changed in place), up, floor, stats) -> objects found from depth
DiscoverFn = Callable[[Callable[[int], Optional[np.ndarray]], list, list[ObjectObservation], object,
                       Optional[float], PipelineStats], list[ObjectObservation]]


def discover_from_depth(colour_of: Callable[[int], Optional[np.ndarray]], views, objects: list[ObjectObservation],
                        up, floor: Optional[float], stats: PipelineStats) -> list[ObjectObservation]:
    """The room's structure and its unnamed objects from the views' depth (`sg3d.ingest.discover.discovery`);
    the named objects get their whole boxes in place."""
    from sg3d.ingest.discover.room_cloud import room_cloud

    return _discovered(colour_of, room_cloud(views, up, floor), objects, stats)


def discover_with_windows(colour_of: Callable[[int], Optional[np.ndarray]], views, objects: list[ObjectObservation],
                          up, floor: Optional[float], stats: PipelineStats) -> list[ObjectObservation]:
    """What `discover_from_depth` finds, and the windows where the floor was seen
    (`sg3d.ingest.discover.windows`: a sill's height is measured from the floor)."""
    from sg3d.ingest.discover.room_cloud import room_cloud
    from sg3d.ingest.discover.windows import windows

    cloud = room_cloud(views, up, floor)
    found = _discovered(colour_of, cloud, objects, stats)
    if cloud.floor_seen:
        nodes = [discovery.structure_node(f"w{k}", e, cloud) for k, e in enumerate(windows(cloud))]
        stats.structure += len(nodes)
        found += nodes
    return found


def depth_discovery(settings: Settings) -> DiscoverFn:
    """Discovery from depth as `settings` ask: with the windows (`discover_with_windows`) only for a
    walk (`Settings.windows`): their own plane vote and every view's rays cost a single-room build
    seconds it has no use for."""
    return discover_with_windows if settings.windows else discover_from_depth


def _discovered(colour_of: Callable[[int], Optional[np.ndarray]], cloud, objects: list[ObjectObservation],
                stats: PipelineStats) -> list[ObjectObservation]:
    from sg3d.ingest.discover.structure import room_structure

    colour_image = functools.lru_cache(maxsize=16)(colour_of)   # objects side by side are read in the same views
    unnamed, nodes = discovery.discover(objects, cloud, room_structure(cloud), colour_image)
    stats.unnamed += len(unnamed)
    stats.structure += len(nodes)
    return unnamed + nodes


def at_fixed_precision(o: ObjectObservation) -> ObjectObservation:
    """An object's geometry (mean, variance, size, box centre, surface sample) as the graph
    keeps it, to a fixed precision (`sg3d.core.geometry.fixed_precision`): what relations,
    the merge and the store see is the same on any CPU. Changed in place, returned."""
    o.mean = vec3(fixed_precision(o.mean))
    o.var = vec3(fixed_precision(o.var, 2 * METRES_DECIMALS))
    o.size = vec3(fixed_precision(o.size))
    if o.box_centre is not None:
        o.box_centre = vec3(fixed_precision(o.box_centre))
    if o.surface is not None:
        o.surface = tuple(float(v) for v in fixed_precision(o.surface))
    return o


def _centre(o: ObjectObservation) -> tuple[float, float, float]:
    """The centre of an object's box (its Gaussian mean where no box was measured)."""
    return o.box_centre if o.box_centre is not None else o.mean


def _structure_relations(objects: list[ObjectObservation], up) -> list[RelationObservation]:
    """What the objects stand ON of the room's structure (floor, counters, shelves; not walls),
    from their fused boxes; structure takes part in no other relation."""
    structure = {o.local_id for o in objects if o.layer == "structure" and o.label not in ("wall", "window")}
    if not structure:
        return []
    geoms = [ObjectGeometry(o.local_id, o.label, _centre(o), o.size) for o in objects
             if o.layer != "structure" or o.local_id in structure]
    things = [g for g in geoms if g.local_id not in structure]
    geoms = [floor_under_room(g, things, up) if g.label == "floor" else g for g in geoms]
    return [r for r in spatial_relations(geoms, up)
            if r.predicate == "ON" and r.object in structure and r.subject not in structure]


def sequence_colour(seq) -> Callable[[int], Optional[np.ndarray]]:
    """Frame index -> its colour image read again from `seq` (None when it cannot be read): the
    colour file only, its depth left undecoded (discovery reads colour again for tens of views)."""
    def colour(index: int) -> Optional[np.ndarray]:
        try:
            return seq.frame(index, lazy=True).color
        except FrameError:
            return None
    return colour


def chunk_graph(seq, a: int, b: int, detector: Detector, up, settings: Settings, room: str,
                building: str, key: Optional[str], stats: PipelineStats,
                progress: Optional[ProgressFn] = None, known: Sequence[KnownObject] = (),
                scan: Optional[ScanInfo] = None, floor: Optional[float] = None) -> LocalGraph:
    """The local 3-D scene graph of frames [a, b) of `seq`; with the room's `known` objects
    (a re-scan), also the frames that saw each one's place empty (`sg3d.ingest.objects.rescan`)."""
    basis = horizontal_frame(up)
    stats.chunks += 1
    stats.frames += b - a
    loading = _prepare_in_background(detector)
    chosen = select_frames_to_detect(seq, a, b, settings, stats, progress)
    loading.join()
    sightings, views = _detect(seq, chosen, detector, up, basis, settings, stats, progress, floor)
    return graph_of_evidence(sightings, views, sequence_colour(seq), up, settings, room, building, key, stats,
                             known=known, scan=scan, floor=floor)


def graph_of_evidence(sightings: list[fusion.Sighting], views: list[existence.View],
                      colour_of: Callable[[int], Optional[np.ndarray]], up, settings: Settings, room: str,
                      building: str, key: Optional[str], stats: PipelineStats,
                      known: Sequence[KnownObject] = (), scan: Optional[ScanInfo] = None,
                      floor: Optional[float] = None, discover: Optional[DiscoverFn] = None) -> LocalGraph:
    """The local graph of what detection saw: `sightings` and `views` of the detected frames (in
    frame order), fused into object hypotheses, kept by existence, completed by discovery from
    depth (`colour_of` reads a frame's colour image again), related. A build's chunk and a live
    map's every publish both end here, so the same frames give the same graph. `discover`
    replaces discovery from depth (`discover_from_depth`, same arguments): a live map between two full
    discoveries carries the last one's findings over."""
    method = settings.method
    basis = horizontal_frame(up)
    t0 = time.perf_counter()
    if method.three_d:
        hyps = fusion.consolidate(fusion.associate(sightings))
    else:  # a 2-D graph: every detection of every frame is its own node
        hyps = [fusion.Hypothesis(k, [s]) for k, s in enumerate(sightings)]
    stats.hypotheses += len(hyps)
    if method.sdr:
        kept = _existing(hyps, views, basis, stats)
    else:
        kept = [(h, h.labels, h.scores) for h in hyps]
    stats.kept += len(kept)
    by_id = {f"h{h.hid}": h for h, _, _ in kept}
    objects = [fusion.fuse(f"h{h.hid}", h, basis, labels, scores) for h, labels, scores in kept]
    stats.seconds["fusion"] += time.perf_counter() - t0
    if method.sdr and settings.discover and views:
        t0 = time.perf_counter()
        objects += (discover or depth_discovery(settings))(colour_of, views, objects, up, floor, stats)
        by_id = {k: h for k, h in by_id.items() if k in {o.local_id for o in objects}}   # discovery may drop a misreading
        stats.seconds["discovery"] += time.perf_counter() - t0
    objects = [at_fixed_precision(o) for o in objects]
    t0 = time.perf_counter()
    relations = _relations(by_id, objects, up, method) if method.three_d else []
    stats.seconds["relations"] += time.perf_counter() - t0
    stats.objects += len(objects)
    stats.relations += len(relations)
    t0 = time.perf_counter()
    empty = rescan.empty_places(known, views, basis) if known else {}
    stats.seconds["rescan"] += time.perf_counter() - t0
    return LocalGraph(room=room, building=building, objects=objects, relations=relations, key=key,
                      frames=[v.index for v in views], up=vec3(up),
                      scan=scan, empty_places=empty)
