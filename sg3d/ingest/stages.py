"""The build's stages, each a function from its input to a frozen result carrying its own counts
and seconds: select -> detect -> objects -> discover -> relate (-> rescan). `sg3d.ingest.pipeline`
runs them over a chunk; `PipelineStats.add` sums their results for the build's summary.

Every stage is timed by `timed`, never by hand: the seconds a result carries are the wall time of
the stage's function under its phase name (the summary's "seconds" keys).
"""
from __future__ import annotations

import functools
import time
from collections import Counter, defaultdict
from dataclasses import dataclass, field, replace
from typing import Any, Callable, ClassVar, Iterator, Mapping, Optional, Sequence, TypeVar

import numpy as np

from sg3d.core.geometry import METRES_DECIMALS, Ground, fixed_precision, horizontal_frame
from sg3d.core.model import KnownObject, ObjectObservation, RelationObservation, vec3
from sg3d.ingest.config import BuildConfig, Method
from sg3d.ingest.detect.irrelevant import reject_irrelevant
from sg3d.ingest.detect.models import Detection, Detector
from sg3d.ingest.discover import discovery
from sg3d.ingest.discover.shelves import frame_of_board
from sg3d.ingest.objects import existence, fusion, rescan
from sg3d.ingest.objects.attributes import measure_object
from sg3d.ingest.objects.colour import is_screen
from sg3d.ingest.readers.frames import Frame, FrameError
from sg3d.ingest.relate.relations import (
    ObjectGeometry,
    floor_under_room,
    side_by_side_on_one_support,
    spatial_relations,
)
from sg3d.ingest.relate.sdr import filter_relations, vote_relations, with_whole_geometry
from sg3d.ingest.select.selection import choose_detected_frames

ProgressFn = Callable[[str, int, int], None]   # (phase, done, total)
ColourFn = Callable[[int], Optional[np.ndarray]]  # frame index -> its colour image (None: unreadable)


@dataclass(frozen=True, kw_only=True)
class StageResult:
    """What every stage returns besides its output: its counts (the int and Counter fields of the
    result named in `COUNTED`) and its seconds per phase."""

    seconds: Mapping[str, float] = field(default_factory=dict)
    COUNTED: ClassVar[tuple[str, ...]] = ()   # names of the fields PipelineStats adds up

    def counts(self) -> dict[str, Any]:
        return {name: getattr(self, name) for name in self.COUNTED}


R = TypeVar("R", bound=StageResult)


def timed(phase: str) -> Callable[[Callable[..., R]], Callable[..., R]]:
    """A stage's function, its result carrying its wall time under `phase` (added to what the
    result already says of that phase)."""
    def wrap(fn: Callable[..., R]) -> Callable[..., R]:
        @functools.wraps(fn)
        def run(*args: Any, **kwargs: Any) -> R:
            t0 = time.perf_counter()
            result = fn(*args, **kwargs)
            elapsed = time.perf_counter() - t0
            return replace(result, seconds={**result.seconds, phase: result.seconds.get(phase, 0.0) + elapsed})
        return run
    return wrap


# --------------------------------------------------------------------------------------- select
@dataclass(frozen=True, kw_only=True)
class Selected(StageResult):
    frames: tuple[int, ...]         # frame indices to detect, in order
    in_range: int                   # frames in the range asked for
    read: int = 0                   # frames that reached ABIR with a readable image
    blurry: int = 0
    keyframes: int = 0
    anchors: int = 0
    coverage: int = 0               # extra frames chosen for new viewpoints
    COUNTED = ("read", "blurry", "keyframes", "anchors", "coverage")


@timed("select")
def select_frames(seq: Any, span: tuple[int, int], method: Method, config: BuildConfig,
                  progress: Optional[ProgressFn] = None) -> Selected:
    """Frame indices of `span` [a, b) to run the detector on, in order (every frame when the method
    is not efficient; else `choose_detected_frames`)."""
    a, b = span
    if not method.efficient:
        chosen = [frame.index for frame in seq.frames(a, b, lazy=True)]   # decoded later; a bad image is skipped then
        return Selected(frames=tuple(chosen), in_range=b - a, read=len(chosen))

    def on_frame(frame: Frame, decision: Any, role: str) -> None:
        if progress is not None and frame.index % 25 == 0:
            progress("selecting", frame.index - a + 1, b - a)

    choice = choose_detected_frames(seq, a, b, params=config.selection, on_frame=on_frame)
    st = choice.stats
    return Selected(frames=tuple(choice.detected), in_range=b - a, read=st.read, blurry=st.blurry,
                    keyframes=st.keyframes, anchors=st.anchors, coverage=choice.coverage)


# --------------------------------------------------------------------------------------- detect
@dataclass(frozen=True, kw_only=True)
class Boxes(StageResult):
    """The detector's boxes on one frame."""

    boxes: list[Detection]
    detected: int = 1
    COUNTED = ("detected",)


@dataclass(frozen=True, kw_only=True)
class Lifted(StageResult):
    """One frame's boxes lifted to 3-D with their attributes."""

    sightings: list[fusion.Sighting]


@timed("detect")
def frame_boxes(frame: Frame, detector: Detector, sdr: bool) -> Boxes:
    """The detector's boxes on one decoded frame, irrelevant classes dropped under SDR."""
    dets = detector.detect(frame.color)
    return Boxes(boxes=reject_irrelevant(dets) if sdr else dets)


@timed("attributes")
def lifted(frame: Frame, dets: list[Detection], ground: Ground) -> Lifted:
    """A frame's detections lifted to 3-D with their attributes (boxes without depth drop out),
    measured off the floor when the build knows it (`measure_object`)."""
    screens = [det.box for det in dets if is_screen(det.label)]
    sightings = []
    for det in dets:
        attrs = measure_object(frame, det.box, ground.up, det.label, screens, ground.floor)
        if attrs is not None:
            sightings.append(fusion.Sighting.of(frame.index, det, attrs, ground.basis))
    return Lifted(sightings=sightings)


@dataclass(frozen=True, kw_only=True)
class Detected(StageResult):
    sightings: list[fusion.Sighting]
    views: list[existence.View]
    detected: int                   # frames the detector ran on
    detections: int                 # detections lifted to 3-D
    COUNTED = ("detected", "detections")


def _lazy_frames(seq: Any, chosen: Sequence[int]) -> Iterator[Frame]:
    for i in chosen:
        try:
            yield seq.frame(i, lazy=True)
        except FrameError:
            continue                      # recorded in seq.skipped


def detect_frames(seq: Any, chosen: Sequence[int], detector: Detector, ground: Ground, sdr: bool,
                  progress: Optional[ProgressFn] = None) -> Detected:
    """Sightings and visibility views of the chosen frames (the next frame's images decoded on a
    reader thread while this one is detected)."""
    from sg3d.ingest.readers.frames import decoded_ahead

    sightings: list[fusion.Sighting] = []
    views: list[existence.View] = []
    seconds: dict[str, float] = defaultdict(float)
    position = {i: n for n, i in enumerate(chosen)}
    for frame in decoded_ahead(_lazy_frames(seq, chosen), ("color", "depth"), ahead=2):
        n = position[frame.index]
        try:
            frame.load()
        except FrameError:
            continue                      # recorded in seq.skipped
        boxes = frame_boxes(frame, detector, sdr)
        found = lifted(frame, boxes.boxes, ground)
        for part in (boxes, found):
            for phase, s in part.seconds.items():
                seconds[phase] += s
        sightings.extend(found.sightings)
        views.append(existence.View.of(frame))
        frame.release()
        if progress is not None:
            progress("detecting", n + 1, len(chosen))
    return Detected(sightings=sightings, views=views, detected=len(views), detections=len(sightings),
                    seconds=dict(seconds))


# -------------------------------------------------------------------------------------- objects
@dataclass(frozen=True)
class Evidence:
    """What detection saw, as fusion, discovery and relations read it: the sightings and views of
    the detected frames (in frame order), their colour images read again, the gravity frame."""

    sightings: list[fusion.Sighting]
    views: list[existence.View]
    colour_of: ColourFn
    ground: Ground


@dataclass(frozen=True, kw_only=True)
class Objects(StageResult):
    objects: list[ObjectObservation]
    by_id: dict[str, fusion.Hypothesis]       # local id -> its hypothesis
    hypotheses: int
    kept: int
    rejected: Counter = field(default_factory=Counter)   # reason -> hypotheses
    COUNTED = ("hypotheses", "kept", "rejected")


@timed("fusion")
def fuse_objects(evidence: Evidence, method: Method, config: BuildConfig) -> Objects:
    """Fusion of the sightings into object hypotheses (every detection its own node in a 2-D
    graph), kept by SDR's existence test and size prior."""
    basis = evidence.ground.basis
    if method.three_d:
        hyps = fusion.consolidate(fusion.associate(evidence.sightings))
    else:  # a 2-D graph: every detection of every frame is its own node
        hyps = [fusion.Hypothesis(k, [s]) for k, s in enumerate(evidence.sightings)]
    rejected: Counter = Counter()
    if method.sdr:
        kept = _existing(hyps, evidence.views, basis, rejected, config.objects.min_detections)
    else:
        kept = [(h, h.labels, h.scores) for h in hyps]
    return Objects(objects=[fusion.fuse(f"h{h.hid}", h, basis, labels, scores) for h, labels, scores in kept],
                   by_id={f"h{h.hid}": h for h, _, _ in kept}, hypotheses=len(hyps), kept=len(kept),
                   rejected=rejected)


def _existing(hyps: list[fusion.Hypothesis], views: list[existence.View], basis: np.ndarray, rejected: Counter,
              min_detections: int) -> list[tuple[fusion.Hypothesis, list[str], list[float]]]:
    """SDR's existence test and the size prior over every hypothesis: the kept ones with their
    labels (those the size prior allows); rejections are counted by reason into `rejected`."""
    kept = []
    for h in hyps:
        labels, scores = existence.plausible_labels(h.labels, h.scores, *existence.judged_sizes(h.sightings, h.hi - h.lo))
        if not labels:
            rejected["implausible size for its label"] += 1
            continue
        centre = basis.T @ ((h.lo + h.hi) / 2)
        ev = existence.evidence(centre, h.extent, set(h.frames), views)
        if existence.tile_artefact([s.detection for s in h.sightings]):
            rejected["named only in tiles, though big enough for the full frame"] += 1
        elif ev.detected < min_detections:
            rejected["seen once"] += 1
        elif not existence.exists(ev, min_detections=min_detections):
            rejected["rarely detected where visible"] += 1
        else:
            kept.append((h, labels, scores))
    return kept


# ------------------------------------------------------------------------------------- discover
@dataclass(frozen=True, kw_only=True)
class Discovered(StageResult):
    objects: list[ObjectObservation]          # unnamed objects, then the structure's nodes
    unnamed: int = 0                          # objects found from depth that no detector named
    structure: int = 0                        # floor, walls and surfaces
    COUNTED = ("unnamed", "structure")


# (evidence, the named objects (changed in place)) -> what discovery found
DiscoverFn = Callable[[Evidence, list[ObjectObservation]], Discovered]


def discover_from_depth(evidence: Evidence, objects: list[ObjectObservation]) -> Discovered:
    """The room's structure and its unnamed objects from the views' depth (`sg3d.ingest.discover.discovery`);
    the named objects get their whole boxes in place."""
    from sg3d.ingest.discover.room_cloud import room_cloud

    cloud = room_cloud(evidence.views, evidence.ground.up, evidence.ground.floor)
    unnamed, nodes = _discovered(evidence, objects, cloud)
    return Discovered(objects=unnamed + nodes, unnamed=len(unnamed), structure=len(nodes))


def discover_with_windows(evidence: Evidence, objects: list[ObjectObservation]) -> Discovered:
    """What `discover_from_depth` finds, and the windows where the floor was seen
    (`sg3d.ingest.discover.windows`: a sill's height is measured from the floor)."""
    from sg3d.ingest.discover.room_cloud import room_cloud
    from sg3d.ingest.discover.windows import windows

    cloud = room_cloud(evidence.views, evidence.ground.up, evidence.ground.floor)
    unnamed, nodes = _discovered(evidence, objects, cloud)
    if cloud.floor_seen:
        nodes += [discovery.structure_node(f"w{k}", e, cloud) for k, e in enumerate(windows(cloud))]
    return Discovered(objects=unnamed + nodes, unnamed=len(unnamed), structure=len(nodes))


def _discovered(evidence: Evidence, objects: list[ObjectObservation],
                cloud: Any) -> tuple[list[ObjectObservation], list[ObjectObservation]]:
    """The unnamed objects and the structure's nodes of the room's `cloud` (`discovery.discover`)."""
    from sg3d.ingest.discover.structure import room_structure

    colour_image = functools.lru_cache(maxsize=16)(evidence.colour_of)   # objects side by side are read in the same views
    return discovery.discover(objects, cloud, room_structure(cloud), colour_image)


def depth_discovery(config: BuildConfig) -> DiscoverFn:
    """Discovery from depth as `config` asks: with the windows (`discover_with_windows`) only for a
    walk (`DiscoverConfig.windows`): their own plane vote and every view's rays cost a single-room
    build seconds it has no use for."""
    return discover_with_windows if config.discover.windows else discover_from_depth


@timed("discovery")
def discover_objects(evidence: Evidence, objects: list[ObjectObservation], find: DiscoverFn) -> Discovered:
    """Discovery from depth by `find` (`discover_from_depth`, or a live map's stand-in), timed."""
    return find(evidence, objects)


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


# --------------------------------------------------------------------------------------- relate
@dataclass(frozen=True, kw_only=True)
class Related(StageResult):
    relations: list[RelationObservation]
    objects: int                    # objects of the graph
    COUNTED = ("objects", "relations")

    def counts(self) -> dict[str, Any]:
        return {"objects": self.objects, "relations": len(self.relations)}


@timed("relations")
def relate(hyps: dict[str, fusion.Hypothesis], objects: list[ObjectObservation], ground: Ground, method: Method,
           config: BuildConfig) -> Related:
    """Relations of every detected frame between the objects it shows, voted (SDR) across frames,
    then completed by the fused objects' own boxes (`with_whole_geometry`); none in a 2-D graph."""
    relations = _relations(hyps, objects, ground.up, method, config) if method.three_d else []
    return Related(relations=relations, objects=len(objects))


def _relations(hyps: dict[str, fusion.Hypothesis], objects: list[ObjectObservation], up: Any,
               method: Method, config: BuildConfig) -> list[RelationObservation]:
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
    rc = config.relate
    voted = vote_relations(frames, co_observed=dict(co_observed), majority=rc.vote_majority,
                           min_support=rc.vote_min_support)
    things = [o for o in objects if o.layer != "structure"]
    whole = spatial_relations([ObjectGeometry(o.local_id, o.label, _centre(o), o.size) for o in things], up)
    relations = with_whole_geometry(voted, whole)
    labels = {o.local_id: o.label for o in objects}
    centres = {o.local_id: o.mean for o in objects}
    # between objects as ever; then what each stands on of the room's structure
    return (side_by_side_on_one_support(filter_relations(relations, labels, centres, threshold=rc.prior_threshold))
            + filter_relations(_structure_relations(objects, up), labels, centres, threshold=rc.prior_threshold))


def _centre(o: ObjectObservation) -> tuple[float, float, float]:
    """The centre of an object's box (its Gaussian mean where no box was measured)."""
    return o.box_centre if o.box_centre is not None else o.mean


def _structure_relations(objects: list[ObjectObservation], up: Any) -> list[RelationObservation]:
    """What the objects stand ON of the room's structure (floor, counters, shelves; not walls),
    from their fused boxes; structure takes part in no other relation."""
    structure = {o.local_id for o in objects if o.layer == "structure" and o.label not in ("wall", "window")}
    if not structure:
        return []
    geoms = [ObjectGeometry(o.local_id, o.label, _centre(o), o.size) for o in objects
             if o.layer != "structure" or o.local_id in structure]
    things = [g for g in geoms if g.local_id not in structure]
    geoms = [floor_under_room(g, things, up) if g.label == "floor" else g for g in geoms]
    on = [r for r in spatial_relations(geoms, up)
          if r.predicate == "ON" and r.object in structure and r.subject not in structure]
    return on + on_the_frames_of_boards(on, objects, up)


def on_the_frames_of_boards(on: list[RelationObservation], objects: list[ObjectObservation],
                            up: Any) -> list[RelationObservation]:
    """Rule "what rests on a board rests on its frame": a surface of the room's structure that is
    a board of an object around it (`shelves.frame_of_board`: a bookcase's, a cabinet's open
    shelf) makes each thing ON it ON that object too ("the cup on the bookcase")."""
    R = horizontal_frame(up)

    def box(o: ObjectObservation) -> tuple[np.ndarray, np.ndarray]:
        c, half = R @ np.asarray(_centre(o), float), np.asarray(o.size, float) / 2
        return c - half, c + half

    boards = {r.object for r in on}
    frames = [(o.local_id, *box(o)) for o in objects if o.layer != "structure" and o.size is not None]
    owner = {}
    for o in objects:
        if o.local_id in boards and o.size is not None:
            lo, hi = box(o)
            if (f := frame_of_board(float(hi[2]), lo, hi, frames)) is not None:
                owner[o.local_id] = f
    return [RelationObservation(r.subject, "ON", owner[r.object], r.score) for r in on
            if r.object in owner and r.subject != owner[r.object]]


# --------------------------------------------------------------------------------------- rescan
@dataclass(frozen=True, kw_only=True)
class Rescanned(StageResult):
    empty_places: dict[str, list[int]]       # stored object id -> frames that saw its place empty


@timed("rescan")
def rescanned(known: Sequence[KnownObject], evidence: Evidence) -> Rescanned:
    """With the room's `known` objects (a re-scan), the frames that saw each one's place empty
    (`sg3d.ingest.objects.rescan`)."""
    return Rescanned(empty_places=rescan.empty_places(known, evidence.views, evidence.ground.basis) if known else {})



# -------------------------------------------------------------------------------------- gravity
@dataclass(frozen=True, kw_only=True)
class Grounded(StageResult):
    ground: Ground


@timed("gravity")
def find_ground(seq: Any, span: tuple[int, int]) -> Grounded:
    """Gravity and the floor from the frames of `span` (estimated poses exist only for those; and a
    recording cut from a longer one gives the same room). ValueError: no frame has usable depth."""
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames

    gravity = estimate_gravity(sample_frames(seq, 20, *span))
    return Grounded(ground=Ground(gravity.up, gravity.floor_height))
