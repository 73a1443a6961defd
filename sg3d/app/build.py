"""Build (or extend) a room's scene graph from a sequence: the one function every front end calls.

ingest turns the sequence into local graphs chunk by chunk; each is merged into the store as one
transaction under a key made of the build's identity and the chunk's frame range. A chunk whose
key is already in the store is not read again, so re-running a build, or `--resume` after a
crash or Ctrl-C, merges exactly what is missing and ends with the graph of one clean build.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Callable, Optional

from sg3d.core.errors import Sg3dError
from sg3d.graphdb.protocol import GraphStore

ProgressFn = Callable[[str, int, int], None]
# None when the store's disk has room, else the line saying it is full (`sg3d.app.stores.disk_check`).
DiskCheck = Callable[[], Optional[str]]


class BuildError(Sg3dError, ValueError):
    """Bad input to a build (the front end shows it as one line)."""


@dataclass(frozen=True)
class BuildRequest:
    sequence: Path
    room: str
    building: str = "default"
    layout: Optional[str] = None
    start: int = 0
    stop: Optional[int] = None
    transform_file: Optional[Path] = None
    align_to: Optional[str] = None
    shared_frame: bool = False
    bag_options: Optional[dict] = None  # ROS bags: `sg3d.ingest.readers.bag.BagOptions` fields
    estimate_poses: bool = False        # ignore the recording's poses and estimate them
    trajectory_out: Optional[Path] = None  # write the estimated trajectory here (TUM format)
    wait: bool = False                  # wait for another writer of the room instead of refusing
    rooms: Optional[str] = None         # "auto": find the rooms of the walk too (`sg3d.app.places`)


def check_names(room: str, building: str, error: type[Exception] = BuildError) -> None:
    """`error` unless both can name a room and a building (`sg3d.app.bounds.name_problem`: the rule
    the CLI and `POST /ingest` apply; a room's id is building/room)."""
    from sg3d.app.bounds import name_problem

    problem = name_problem(room, "room") or name_problem(building, "building")
    if problem:
        raise error(problem)


def validate(req: BuildRequest) -> None:
    check_names(req.room, req.building)
    if req.rooms not in (None, "auto"):
        raise BuildError(f"--rooms {req.rooms}: only 'auto' (find the rooms of the walk) is known")
    if sum(map(bool, (req.transform_file, req.align_to, req.shared_frame))) > 1:
        raise BuildError("give at most one of --transform, --align-to and --shared-frame")
    if req.trajectory_out is not None and not Path(req.trajectory_out).expanduser().parent.is_dir():
        raise BuildError(f"--trajectory-out {req.trajectory_out}: no such folder {Path(req.trajectory_out).parent}")
    if req.start < 0 or (req.stop is not None and req.stop <= req.start):
        raise BuildError(f"empty frame range: --start {req.start} --stop {req.stop} "
                         f"(stop must be greater than start, start at least 0)")


def check_frame_selection_options(method: str, given: list[str]) -> None:
    """The basic presets (2d-basic, 3d-basic: paper Table I without the efficient modules) detect
    every frame, so ABIR and KGE never run and their options would change nothing: refuse them
    rather than accept a setting that is silently ignored."""
    from sg3d.ingest.pipeline import METHODS

    if given and not METHODS[method].efficient:
        raise BuildError(f"{', '.join(given)} tune{'s' if len(given) == 1 else ''} ABIR/KGE frame selection, "
                         f"which --method {method} does not run (it detects every frame); "
                         f"drop {'it' if len(given) == 1 else 'them'} or use an efficient preset")


def check_detector(settings):
    """The build's detector; an unknown detector, a missing ONNX labels file or a recogniser that
    cannot run offline is refused before anything starts (nothing is loaded here)."""
    from sg3d.ingest.detect.choice import detector_for

    try:
        return detector_for(settings.detector, settings.score_threshold, tiles=settings.quality == "high")
    except (ValueError, FileNotFoundError, RuntimeError) as exc:
        raise BuildError(str(exc))


@dataclass(frozen=True)
class PreparedBuild:
    """A checked build request with what it needs that no store holds: the detector and the
    room-to-building transform read from `--transform`."""
    req: BuildRequest
    settings: Any                   # sg3d.ingest.pipeline.Settings
    detector: Any
    placement: Optional[Any] = None  # 4x4 array


def prepare(req: BuildRequest, settings, detector=None, selection_given: tuple[str, ...] = ()) -> PreparedBuild:
    """Check everything a build can check before the store starts, in this order: the request,
    the frame-selection options given (`selection_given`: their flags), the detector
    (`check_detector`), the transform file (read before the long build, to fail early)."""
    from sg3d.app.places import walk_settings

    validate(req)
    settings = walk_settings(settings, req.rooms)
    check_frame_selection_options(settings.method.name, list(selection_given))
    detector = detector if detector is not None else check_detector(settings)
    placement = None
    if req.transform_file is not None:
        from sg3d.graphdb.building import TransformError, load_transform

        try:
            placement = load_transform(req.transform_file)
        except TransformError as exc:
            raise BuildError(str(exc))
    return PreparedBuild(req, settings, detector, placement)


@dataclass
class BuildSummary:
    """What a build did, as `sg3d build` prints it and `--json` writes it (`as_dict`). The
    sections are the JSON's objects; `summary["graph"]` reads like the JSON."""
    sequence: str
    layout: str
    room: str
    building: str
    method: str
    quality: str
    detector: str
    interrupted: bool
    up: list[float]
    frames: dict                    # in_range, read, blurry, keyframes, ..., skipped, skipped_frames
    hypotheses: dict                # formed, kept, rejected (reason -> n)
    from_depth: dict                # found from depth, named by no detector: unnamed, structure
    graph: dict                     # chunk and object totals, room_objects, room_relations
    seconds: dict                   # per phase
    input_frames_per_second: float
    key: str
    scan: str
    placement: Optional[dict]
    poses: dict
    # "seen", or "not seen": the recording never saw the floor (a desk scan), so its tops are objects
    floor: str = "seen"
    rooms_found: Optional[dict] = None   # --rooms auto: `sg3d.app.places.write_walk_rooms`

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __getitem__(self, name: str):
        return getattr(self, name)

    def get(self, name: str, default=None):
        return getattr(self, name, default)


def build_room(store: GraphStore, req: BuildRequest, settings, detector=None, embedding=None,
               progress: Optional[ProgressFn] = None) -> BuildSummary:
    """Run the pipeline over `req.sequence` and merge each chunk into `store` (`prepare`, then
    `run_build`). `settings`: `sg3d.ingest.pipeline.Settings`."""
    return run_build(store, prepare(req, settings, detector), embedding, progress)


def run_build(store: GraphStore, prepared: PreparedBuild, embedding=None, progress: Optional[ProgressFn] = None,
              disk_check: Optional[DiskCheck] = None) -> BuildSummary:
    """A prepared build: the sequence read, its camera poses and gravity, each chunk's local
    graph merged into `store`, the room placed. The room is held for the whole build (one writer
    per room: `sg3d.app.writers.writing`). KeyboardInterrupt between chunks keeps what was merged
    and returns a summary with `interrupted` set. `disk_check` (`sg3d.app.stores.disk_check`) is
    asked before every merge transaction: a disk below the store's minimum is refused, not written."""
    from sg3d.app.writers import writing

    req = prepared.req
    seq, stop = _open(req)
    store.ensure_schema()
    with writing(store, req.building, req.room, "build", f"sg3d build {req.sequence}", wait=req.wait,
                 error=BuildError) as lease:
        return _run_held(store, prepared, seq, stop, lease, embedding, progress, disk_check)


def _run_held(store: GraphStore, prepared: PreparedBuild, seq, stop: int, lease, embedding,
              progress: Optional[ProgressFn], disk_check: Optional[DiskCheck]) -> BuildSummary:
    from sg3d.core.embedding import default_embedding
    from sg3d.merge.similarity import SimilarityParams
    from sg3d.graphdb.values import room_id
    from sg3d.ingest.pipeline import PipelineStats, run_key

    req, settings = prepared.req, prepared.settings
    t_start = time.perf_counter()
    poses = place_cameras(seq, req, stop, progress)
    # a build on estimated poses is another build than one on the recording's own poses
    identity = str(Path(req.sequence).resolve()) + (" (estimated poses)" if poses["source"] == "estimated" else "")
    run = run_key(identity, len(seq), settings, req.room, req.building)
    scan = scan_key(run, req.start, stop)
    done, forgotten = merged_chunks(store, room_id(req.building, req.room), run, scan)
    t0 = time.perf_counter()
    gravity = _gravity(seq, req, stop)
    t_gravity = time.perf_counter() - t0
    chunks = _Chunks(store, seq, req, settings, prepared.detector, gravity, embedding or default_embedding(),
                     SimilarityParams() if settings.method.three_d else SimilarityParams(threshold=float("inf")),
                     run, done, scan, PipelineStats(), progress, lease.fence, disk_check)
    chunks.totals["remerged_chunks"] = forgotten
    chunks.merge_all(req.start, stop)
    placed = None if chunks.interrupted else place_room(store, req, prepared.placement)
    found, t_rooms = None, time.perf_counter()
    if req.rooms == "auto" and not chunks.interrupted:
        from sg3d.app.places import Walk, write_walk_rooms

        found = write_walk_rooms(store, room_id(req.building, req.room),
                                 Walk(seq, req.start, stop, gravity.up, gravity.floor_height), fence=lease.fence)
    t_rooms = time.perf_counter() - t_rooms
    wall = time.perf_counter() - t_start
    summary = _summary(store, room_id(req.building, req.room), seq, req, settings, stop, gravity.up, chunks,
                       {**({"poses": poses["seconds"]} if "seconds" in poses else {}), "gravity": t_gravity,
                        **({"rooms": t_rooms} if found is not None else {})},
                       wall, placed, poses, gravity.floor_height is not None)
    summary.rooms_found = found
    return summary


def merged_chunks(store: GraphStore, rid: str, run: str, scan: str) -> tuple[set, int]:
    """The keys of this build's chunks already merged (not read again), and how many logged chunks
    were forgotten: rule "a merge log without its objects is no merge". When the build's logs say
    it created objects and the room holds none this build's scan saw (someone deleted them), its
    logs are removed and every chunk merges again, and the summary and stderr say so."""
    import logging

    rows = store.read("merge_log_run", prefix=run + ":")
    created = sum(int(r["created"] or 0) for r in rows)
    if not rows or created == 0 or store.read("scan_object_count", room=rid, scan=scan)[0]["n"]:
        return {r["key"] for r in rows}, 0
    store.write("merge_log_forget", prefix=run + ":")
    logging.getLogger("sg3d.build").warning(
        "room %s holds none of the %d objects this build merged before (its %d chunks are logged as merged): "
        "merging every chunk again", rid, created, len(rows))
    return set(), len(rows)


def _open(req: BuildRequest):
    """The sequence and the end of the frame range, refusing an empty sequence or range."""
    from sg3d.ingest.readers import SequenceError, open_sequence

    try:
        seq = open_sequence(req.sequence, req.layout, **(req.bag_options or {}))
    except SequenceError as exc:
        raise BuildError(str(exc)) from None
    if len(seq) == 0:
        raise BuildError(f"no frames found in {req.sequence}")
    if req.start >= len(seq):
        raise BuildError(f"--start {req.start} is past the end of the sequence ({len(seq)} frames)")
    return seq, len(seq) if req.stop is None else min(req.stop, len(seq))


def _gravity(seq, req: BuildRequest, stop: int):
    """Gravity and the floor from the frames being built (estimated poses exist only for those;
    and a recording cut from a longer one gives the same room)."""
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames

    try:
        return estimate_gravity(sample_frames(seq, 20, req.start, stop))
    except ValueError:
        raise BuildError(f"no frame of {req.sequence} has usable depth")


@dataclass
class _Chunks:
    """The build's chunks, each a local graph merged as one transaction under its key; a chunk
    whose key is already merged is not read again."""
    store: GraphStore
    seq: Any
    req: BuildRequest
    settings: Any
    detector: Any
    gravity: Any
    embedding: Any
    params: Any
    run: str
    done: set
    scan_id: str
    stats: Any
    progress: Optional[ProgressFn]
    fence: Any = None                       # the room lease's check, first in each merge transaction
    disk_check: Optional[DiskCheck] = None
    totals: dict = field(default_factory=lambda: {
        "chunks": 0, "merged_chunks": 0, "skipped_chunks": 0, "objects_created": 0, "objects_updated": 0,
        "objects_moved": 0, "objects_removed": 0, "objects_folded": 0, "relations": 0})
    merge_seconds: float = 0.0
    interrupted: bool = False

    def merge_all(self, start: int, stop: int) -> None:
        from sg3d.ingest.pipeline import chunk_ranges

        scan_at = time.time()
        ranges = chunk_ranges(start, stop, self.settings.chunk_frames)
        try:
            for a, b in ranges:
                self.merge_one(a, b, scan_at, closes=(a, b) == ranges[-1])
        except KeyboardInterrupt:
            self.interrupted = True

    def check_disk(self) -> None:
        """BuildError when the store's disk is below its minimum (checked before every merge
        transaction, not only when the store starts: a build must not write past it)."""
        full = self.disk_check() if self.disk_check is not None else None
        if full:
            raise BuildError(f"{full}; {self.totals['merged_chunks']} chunks were merged and are kept, nothing "
                             f"more was written: free space and run the same command again")

    def merge_one(self, a: int, b: int, scan_at: float, closes: bool) -> None:
        from sg3d.core.model import ScanInfo
        from sg3d.graphdb.merge import merge_local_graph
        from sg3d.graphdb.rescan import known_objects
        from sg3d.graphdb.values import room_id
        from sg3d.ingest.pipeline import chunk_graph

        totals, req = self.totals, self.req
        totals["chunks"] += 1
        key = f"{self.run}:{a}-{b}"
        if key in self.done:
            totals["skipped_chunks"] += 1
            return
        self.check_disk()
        # the room as it stands before this chunk: what a re-scan may find moved or gone
        known = known_objects(self.store, room_id(req.building, req.room))
        graph = chunk_graph(self.seq, a, b, self.detector, self.gravity.up, self.settings, req.room, req.building,
                            key, self.stats, self.progress, known=known, scan=ScanInfo(self.scan_id, scan_at, closes=closes),
                            floor=self.gravity.floor_height)
        self.check_disk()
        t0 = time.perf_counter()
        report = merge_local_graph(self.store, graph, self.embedding, self.params, fence=self.fence)
        self.merge_seconds += time.perf_counter() - t0
        totals["merged_chunks"] += 0 if report.skipped else 1
        totals["skipped_chunks"] += 1 if report.skipped else 0
        totals["objects_created"] += report.created
        totals["objects_updated"] += report.updated
        totals["relations"] += report.relations
        totals["objects_moved"] += report.moved
        totals["objects_removed"] += report.removed
        totals["objects_folded"] += report.absorbed


def _summary(store, rid: str, seq, req: BuildRequest, settings, stop: int, up, chunks: _Chunks,
             seconds_before: dict, wall: float, placed, poses: dict, floor_seen: bool = True) -> BuildSummary:
    from sg3d.core.model import RELATION_TYPES

    room_objects = store.read("object_count", room=rid)[0]["n"]
    room_relations = store.read("relation_count", room=rid, types=list(RELATION_TYPES))[0]["n"]
    skipped = [{"frame": name, "reason": reason} for name, reason in seq.skipped]
    counts = chunks.stats.as_dict()
    hyp = {"formed": counts.pop("hypotheses"), "kept": counts.pop("kept"), "rejected": counts.pop("rejected")}
    return BuildSummary(
        sequence=str(req.sequence), layout=seq.layout, room=req.room, building=req.building,
        method=settings.method.name, quality=settings.quality, detector=settings.detector,
        interrupted=chunks.interrupted, up=[round(float(v), 4) for v in up],
        frames={"in_range": stop - req.start, **{k: counts[k] for k in (
            "read", "blurry", "keyframes", "anchors", "coverage", "detected", "detections")},
            "skipped": len(skipped), "skipped_frames": skipped},
        hypotheses=hyp,
        from_depth={"unnamed": counts.get("unnamed", 0), "structure": counts.get("structure", 0)},
        graph={**chunks.totals, "room_objects": room_objects, "room_relations": room_relations},
        seconds={k: round(v, 3) for k, v in {**seconds_before, **chunks.stats.seconds,
                                             "merge": chunks.merge_seconds, "total": wall}.items()},
        input_frames_per_second=round(counts["frames"] / wall, 2) if wall > 0 and counts["frames"] else 0.0,
        key=chunks.run, scan=chunks.scan_id, placement=placed, poses=poses, floor="seen" if floor_seen else "not seen")


def place_cameras(seq, req: BuildRequest, stop: int, progress: Optional[ProgressFn] = None) -> dict:
    """Camera poses for the build: the recording's own, or estimated from its images when it has
    none or `req.estimate_poses` asks; the summary's "poses" section."""
    if not req.estimate_poses and seq.has_poses():
        if req.trajectory_out is not None:
            raise BuildError(f"--trajectory-out writes estimated poses, and {req.sequence} has its own; "
                             f"add --estimate-poses to estimate them anyway")
        return {"source": "given"}
    from sg3d.ingest.poses.sequence import (
        estimate_sequence_poses,
        estimate_summary,
        write_trajectory,
    )

    est = estimate_sequence_poses(seq, req.start, stop,
                                  progress=(lambda done, total: progress("poses", done, total)) if progress else None)
    if not est.poses:
        raise BuildError(f"no camera pose could be estimated for {req.sequence}: "
                         + "; ".join(sorted({why for why in est.unplaced.values()})[:3]))
    if req.trajectory_out is not None:
        try:
            write_trajectory(req.trajectory_out, seq, est)
        except OSError as exc:
            raise BuildError(f"cannot write --trajectory-out {req.trajectory_out}: {exc.strerror}")
    return estimate_summary(seq, est, str(req.trajectory_out) if req.trajectory_out else None)


def scan_key(run: str, start: int, stop: int) -> str:
    """A build's scan id: the build's identity and its frame range (the same build re-run or
    resumed is the same scan; another range of the same sequence is another scan)."""
    return f"{run}@{start}-{stop}"


def place_room(store: GraphStore, req: BuildRequest, transform):
    """Give the room its room-to-building transform; a building's first room is its reference."""
    import numpy as np

    from sg3d.merge.align import AlignmentError
    from sg3d.graphdb.building import link_rooms, list_rooms, set_room_transform
    from sg3d.graphdb.values import room_id

    rid = room_id(req.building, req.room)
    try:
        if req.align_to:
            report = link_rooms(store, room_id(req.building, req.align_to), rid)
            return {"how": f"aligned to {req.align_to}", "residual_m": round(report.residual_rms_m, 4),
                    "pairs": report.pairs, "same_as": len(report.same_as)}
        if transform is not None:
            set_room_transform(store, rid, transform)
            return {"how": "transform file"}
        placed = [r for r in list_rooms(store, req.building) if r["id"] != rid and r["to_building"] is not None]
        if req.shared_frame or not placed:
            set_room_transform(store, rid, np.eye(4))
            return {"how": "shared frame" if req.shared_frame else "reference room of the building"}
    except AlignmentError as exc:
        raise BuildError(f"the graph was built, but placing it in the building failed: {exc}")
    return {"how": "not placed yet: `sg3d rooms link`, or build with --align-to/--transform/--shared-frame"}
