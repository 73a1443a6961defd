"""Map a room live (`sg3d map`): follow a source as frames arrive and keep the room's graph in the
store current, until the source ends, the caller stops it, or no frame came for a while.

Two threads share one `sg3d.ingest.live.LiveMapper`: this one judges every arriving frame and
detects the chosen ones; a publisher recomputes the room's graph from the evidence at most every
`publish_every` seconds and publishes it as one transaction with stable node ids
(`sg3d.graphdb.live.publish`). Readers (`sg3d ask`, `sg3d serve`) read the last committed
publish and never wait for mapping. At the end a source that can be read again (a folder) gets
the frames a build would detect, so the last publish is the graph `sg3d build` gives.

A map killed mid-way left the room with its last publish and the state "live": `--resume` maps
the source again into it; the ids of what was published continue and nothing is duplicated.
"""
from __future__ import annotations

import resource
import threading
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Optional

import numpy as np

from sg3d.app.errors import MapError
from sg3d.graphdb.protocol import GraphStore

if TYPE_CHECKING:
    from sg3d.ingest.config import BuildConfig

# Publishing more often than this gains nothing a reader could see and costs the store writes.
MIN_PUBLISH_EVERY_S = 0.2
# Frames listed per kind of reason in the summary of a map's bad frames (`skipped_by_reason`).
SKIPPED_EXAMPLES = 3
# How often an idle mapper looks for new frames.
POLL_S = 0.03
# --stop-when-idle before any frame arrived: at least this long (a camera or recorder starting up).
FIRST_FRAME_WAIT_S = 30.0
# Discovery from depth (structure, unnamed objects, furniture from shape) runs again at most this
# often, on its own thread: on 2 cores it takes ~0.5-2 s for a room, too long to run before every
# publish; publishes in between carry its findings over (`sg3d.ingest.live.carried_over`).
DISCOVER_EVERY_S = 2.0
# Tracking comes first: discovery's thread runs this much below the process's CPU priority (loop
# closure further below, `live_loops.NICE`), so on busy cores the tracker's thread gets the time it
# needs (at a load of 9 a tracked kitchen frame took 154 ms in `sg3d map` against ~90 ms tracked alone).
DISCOVER_NICE = 5


@dataclass(frozen=True)
class MapRequest:
    source: Path
    room: str
    building: str = "default"
    layout: Optional[str] = None
    publish_every: float = 1.0
    stop_when_idle: Optional[float] = None    # seconds without a new frame; None: until stopped
    resume: bool = False
    wait: bool = False                        # wait for another writer of the room instead of refusing
    trajectory_out: Optional[Path] = None     # the poses tracked online, as a TUM file (pose-less sources)
    rooms: Optional[str] = None               # "auto": the rooms of the walk grow with it (`sg3d.app.places`)


@dataclass
class MapSummary:
    """What a live map did (`sg3d map --json`)."""
    source: str
    room: str
    building: str
    state: str                      # done | stopped
    frames: dict
    objects: int
    relations: int
    publishes: int
    latency_s: dict                 # frame written -> its evidence visible in the store
    first_objects_after_s: Optional[float]   # first frame written -> first published object
    backlog_at_end: int
    seconds: dict
    peak_memory_mib: float
    final: dict = field(default_factory=dict)   # the last publish: made of the frames a build detects
    tracking: Optional[dict] = None  # a source without poses: what online tracking did (`OnlinePoses.summary`)
    stages: dict = field(default_factory=dict)   # per stage: ran / skipped (`_stages`)

    def as_dict(self) -> dict:
        return asdict(self)


def skipped_by_reason(skipped: dict[str, str], examples: int = SKIPPED_EXAMPLES) -> dict:
    """The bad frames of a map as its summary lists them: "skipped" (how many) and
    "skipped_by_reason", one entry per kind of reason (`frames.reason_kind`: the reason without
    frame names and figures), most frequent first, with its count and its first `examples` frames
    (each with its full reason). A map can run for hours: the summary stays this size."""
    from sg3d.ingest.readers.frames import reason_kind

    kinds: dict[str, dict] = {}
    for name, reason in skipped.items():
        kind = kinds.setdefault(reason_kind(name, reason), {"count": 0, "frames": []})
        kind["count"] += 1
        if len(kind["frames"]) < examples:
            kind["frames"].append({"frame": name, "reason": reason})
    listed = [{"reason": k, **v} for k, v in sorted(kinds.items(), key=lambda kv: -kv[1]["count"])]
    return {"skipped": len(skipped), "skipped_by_reason": listed}


def check_request(req: MapRequest) -> None:
    from sg3d.app.build import check_names

    check_names(req.room, req.building, MapError)
    if req.publish_every < MIN_PUBLISH_EVERY_S:
        raise MapError(f"--publish-every {req.publish_every}: at least {MIN_PUBLISH_EVERY_S} s")
    if req.stop_when_idle is not None and req.stop_when_idle <= 0:
        raise MapError(f"--stop-when-idle {req.stop_when_idle}: give a number of seconds above 0")
    if req.trajectory_out is not None and not Path(req.trajectory_out).expanduser().parent.is_dir():
        raise MapError(f"--trajectory-out {req.trajectory_out}: its folder does not exist")
    from sg3d.app.live_sources import source_kind

    source_kind(req.source)      # SourceError (a MapError) when SOURCE names nothing to follow


def check_room(store: GraphStore, req: MapRequest) -> None:
    """A map writes a room of its own: refuse a room that holds a built graph, and a room an
    earlier map left without --resume (say how to go on)."""
    from sg3d.graphdb.live import mapping_status
    from sg3d.graphdb.values import room_id

    status = mapping_status(store, req.building, req.room)
    held = store.read("object_count", room=room_id(req.building, req.room))
    n = held[0]["n"] if held else 0
    if status is None:
        if n:
            raise MapError(f"room {req.room} already holds {n} objects from `sg3d build` or an ingest; "
                           f"map into a new room (or `sg3d rooms delete {req.room}` first)")
        return
    if not req.resume:
        raise MapError(f"room {req.room} was mapped live before ({status.get('frames') or 0} frames, state "
                       f"{status.get('mapping')}); add --resume to map into it again (its objects keep their ids)")


@dataclass(frozen=True)
class Models:
    """The models a live map runs (None: the config's detector, the default label embedding)."""

    detector: Any = None
    embedding: Any = None


def map_room(store: GraphStore, req: MapRequest, settings: BuildConfig,
             on_update: Optional[Callable[[dict], None]] = None,
             should_stop: Optional[Callable[[], bool]] = None, models: Models = Models()) -> MapSummary:
    """Follow `req.source` and keep the room's graph current (module docstring). `on_update` gets
    a small dict after every publish (frames, objects, latency) for progress displays;
    `should_stop` is polled (a test's or a service's stop signal; Ctrl-C stops it too)."""
    detector, embedding = models.detector, models.embedding
    from sg3d.app.build import check_detector
    from sg3d.app.live_sources import open_live_source
    from sg3d.app.places import walk_settings
    from sg3d.app.writers import Writer, writing
    from sg3d.core.embedding import default_embedding
    from sg3d.ingest.live import LiveMapper

    check_request(req)
    detector = detector if detector is not None else check_detector(settings)
    store.ensure_schema()
    with writing(store, req.building, req.room, Writer("map", f"sg3d map {req.source}", wait=req.wait),
                 error=MapError) as lease:
        check_room(store, req)
        follower = open_live_source(req.source, req.layout)   # a folder, a RealSense, an MCAP being recorded
        mapper = LiveMapper(follower, detector, walk_settings(settings, req.rooms), req.room, req.building)
        publisher = _Publisher(store, mapper, req, embedding or default_embedding(), on_update, lease.fence)
        return _map_held(req, detector, follower, mapper, publisher, should_stop)


def _map_held(req: MapRequest, detector, follower, mapper, publisher: "_Publisher",
              should_stop: Optional[Callable[[], bool]]) -> MapSummary:
    """The map itself, while it holds the room: follow, publish, finish (`map_room`)."""
    discoverer = _Discoverer(mapper)
    started = time.time()
    getattr(detector, "prepare", lambda: None)()
    publisher.announce()
    publisher.start()
    discoverer.start()
    getattr(follower, "start", lambda: None)()      # a source tracked online tracks on its own thread
    t_loop = time.perf_counter()
    try:
        state = _follow(mapper, req, should_stop)
    finally:
        getattr(follower, "stop", lambda: None)()
    t_live = time.perf_counter() - t_loop
    discoverer.stop()
    publisher.stop()
    backlog = mapper.backlog()
    t0 = time.perf_counter()
    final: dict[str, Any] = {}
    if state == "done" and follower.seq is not None:
        whole = follower.whole()                    # the recording as a build reads it
        frames = mapper.finish(whole)
        final = {"frames": len(frames), "as_build": True}
        publisher.recording = whole                 # its rooms too, as a build finds them
        publisher.unseen = frozenset()    # a build's frames saw all there is: what they miss is gone
    elif state == "done" and getattr(follower, "posed", True) is False and mapper.gravity is not None:
        # a source tracked live: the tracked frames the budget left undetected are detected now
        # (coverage choice over every judged frame, as `finish` makes it; those no longer held are skipped)
        frames = mapper.finish(None)
        final = {"frames": len(frames), "as_build": False}
    else:
        frames = mapper.detected_frames()
        final = {"frames": len(frames), "as_build": False}
    report = publisher.publish_now(frames, state)
    if req.rooms == "auto":
        final["rooms_found"] = publisher.rooms_found
    t_final = time.perf_counter() - t0
    if mapper.gravity is None and follower.seq is None:
        raise MapError(f"no frame arrived in {req.source} ({follower.waiting_for})")
    c = mapper.counts
    return MapSummary(
        source=str(req.source), room=req.room, building=req.building, state=state,
        frames={"received": c.received, "read": c.read, "blurry": c.blurry, "keyframes": c.keyframes,
                "anchors": c.anchors, "coverage": c.coverage, "detected": c.detected,
                "detected_at_end": c.detected_at_end, "skipped_behind": c.skipped_behind, "jumped": c.jumped,
                **skipped_by_reason(mapper.skipped(follower.seq))},
        objects=report.objects if report else 0, relations=report.relations if report else 0,
        publishes=publisher.publishes, latency_s=publisher.latency(),
        first_objects_after_s=(round(publisher.first_objects_at - follower.written_at(0), 3)
                               if publisher.first_objects_at is not None and c.received else None),
        backlog_at_end=backlog,
        seconds={"live": round(t_live, 3), "final": round(t_final, 3), "total": round(time.time() - started, 3),
                 "publish_mean": round(publisher.mean_seconds(), 3),
                 "graph_mean": round(float(np.mean(publisher.graph_seconds)) if publisher.graph_seconds else 0.0, 3),
                 "discoveries": discoverer.runs,
                 "discovery_mean": round(float(np.mean(discoverer.seconds)) if discoverer.seconds else 0.0, 3),
                 **({"walk_rooms": len(publisher.rooms_seconds),
                     "walk_rooms_mean": round(float(np.mean(publisher.rooms_seconds)), 3)}
                    if publisher.rooms_seconds else {})},
        peak_memory_mib=round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        final=final, tracking=_tracking(follower, req),
        stages=_stages(mapper, follower, publisher, discoverer))


def _stages(mapper, follower, publisher: "_Publisher", discoverer: "_Discoverer") -> dict:
    """Per stage of the live loop, how often it ran and what it skipped (the `--json` "stages"):
    tracking (a source without poses), judging (ABIR + KGE), detection, discovery, publishing."""
    c = mapper.counts
    t = follower.summary() if getattr(follower, "posed", True) is False and hasattr(follower, "summary") else None
    return {"tracking": {"ran": t["ran"], "skipped": t["skipped"]} if t else None,
            "judging": {"ran": c.read, "skipped": c.jumped},
            "detection": {"ran": c.detected - c.detected_at_end, "skipped": c.skipped_behind,
                          "deferred": c.detect_deferred, "at_end": c.detected_at_end},
            "discovery": {"ran": discoverer.runs, "deferred": discoverer.deferred},
            "publishing": {"ran": publisher.publishes}}


def _tracking(follower, req: MapRequest) -> Optional[dict]:
    """What online tracking did (None when the source carried its own poses); writes the tracked
    trajectory to `req.trajectory_out` (TUM) when asked."""
    if getattr(follower, "posed", True) is True or not hasattr(follower, "summary"):
        return None
    if req.trajectory_out is not None:
        from sg3d.ingest.poses.trajectory import write_tum

        times, poses = follower.trajectory()
        try:
            write_tum(req.trajectory_out, times, poses)
        except OSError as exc:
            raise MapError(f"cannot write --trajectory-out {req.trajectory_out}: {exc.strerror}")
    return follower.summary()


def _follow(mapper, req: MapRequest, should_stop: Optional[Callable[[], bool]]) -> str:
    """The mapping loop: judge what arrived (at most 8 frames a turn), detect one chosen frame,
    until the source is idle for `req.stop_when_idle`, `should_stop` says so or Ctrl-C;
    returns "done" or "stopped"."""
    from sg3d.ingest.readers.base import SequenceError

    last_frames, last_change = 0, time.monotonic()
    last_seen = (0, 0)
    try:
        while True:
            if should_stop is not None and should_stop():
                return "stopped"
            try:
                judged = mapper.look(limit=8)
            except SequenceError as exc:
                raise MapError(str(exc))
            detected = mapper.detect_next() if mapper.may_detect() else False
            # idle: nothing arrived and nothing became ready to judge (a recording tracked in
            # order makes frames ready long after they arrived)
            if (mapper.counts.received, mapper.next_frame) != last_seen:
                last_seen, last_change = (mapper.counts.received, mapper.next_frame), time.monotonic()
                last_frames = mapper.counts.received
            if not judged and not detected:
                if req.stop_when_idle is not None:
                    # before the first frame the camera may still be starting: wait longer
                    idle = req.stop_when_idle if last_frames else max(req.stop_when_idle, FIRST_FRAME_WAIT_S)
                    if time.monotonic() - last_change >= idle:
                        return "done"
                time.sleep(POLL_S)
    except KeyboardInterrupt:
        return "stopped"


class _Worker:
    """A loop on its own thread (`_run`, until `_stop` is set); an error ends it and is raised
    again on the mapping thread by `stop()`; it runs `nice` below the process's CPU priority."""

    nice = 0

    def __init__(self, name: str):
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._guarded, name=name, daemon=True)
        self.error: Optional[BaseException] = None

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()
        if self.error is not None:
            raise self.error

    def _guarded(self) -> None:
        from sg3d.ingest.poses.live_loops import lower_thread_priority

        if self.nice:
            lower_thread_priority(self.nice)
        try:
            self._run()
        except Exception as exc:   # noqa: BLE001 - handed to the mapping thread by stop()
            self.error = exc

    def _run(self) -> None:
        raise NotImplementedError


class _Discoverer(_Worker):
    """Runs discovery from depth again every DISCOVER_EVERY_S while the evidence changes."""

    nice = DISCOVER_NICE

    def __init__(self, mapper):
        super().__init__("sg3d-map-discover")
        self.mapper = mapper
        self.runs = 0
        self.deferred = 0
        self.seconds: list[float] = []

    def _run(self) -> None:
        while not self._stop.wait(DISCOVER_EVERY_S):
            m = self.mapper
            if m.gravity is None or (m.discovered is not None and m.discovered.version == m.version):
                continue
            if m.tracked() and m.backlog() > m.max_backlog():   # tracking first: discovery waits
                self.deferred += 1
                continue
            t0 = time.perf_counter()
            m.graph(fast=False)
            self.runs += 1
            self.seconds.append(time.perf_counter() - t0)


class _Publisher(_Worker):
    """Publishes the mapper's graph at most every `publish_every` seconds on its own thread."""

    def __init__(self, store: GraphStore, mapper, req: MapRequest, embedding, on_update, fence=None):
        from sg3d.core.model import ScanInfo
        from sg3d.graphdb.live import map_object_ids

        super().__init__("sg3d-map-publish")
        self.store, self.mapper, self.req, self.embedding = store, mapper, req, embedding
        self.on_update, self.fence = on_update, fence
        # a resumed map has not yet seen again what the killed one published: those nodes stay (and
        # keep their ids when it finds them again) until the end shows whether they are there
        self.unseen = map_object_ids(store, req.building, req.room) if req.resume else frozenset()
        self.since = time.time()
        self.scan = ScanInfo(f"map:{req.building}/{req.room}@{self.since:.0f}", self.since, closes=False)
        self.publishes = 0
        self.published_version = -1
        self.latencies: dict[int, float] = {}
        self.first_objects_at: Optional[float] = None
        self.publish_seconds: list[float] = []
        self.graph_seconds: list[float] = []
        self._lock = threading.Lock()        # one publish at a time (the last one runs after the thread)
        self.recording = None                # the last publish: the whole recording (its rooms as a build finds them)
        self.rooms_at = -float("inf")        # when the rooms of the walk were last found (`_walk_rooms`)
        self.rooms_found: Optional[dict] = None
        self.rooms_seconds: list[float] = []     # each time the rooms of the walk were found and written

    def announce(self) -> None:
        """The room exists and says it is being mapped before the first frame is in."""
        from sg3d.graphdb.merge import ensure_room
        from sg3d.graphdb.values import room_id

        ensure_room(self.store, self.req.building, self.req.room)
        self.store.write("live_status", room=room_id(self.req.building, self.req.room), state="live",
                         since=self.since, frames=0, updated=time.time(), source=str(self.req.source))

    def _run(self) -> None:
        """Publish as soon as the evidence changed and `publish_every` passed since the last
        publish began (a frame detected just after a quiet spell is visible at once)."""
        last = -float("inf")
        while not self._stop.wait(POLL_S):
            if self.mapper.gravity is None or self.mapper.version == self.published_version:
                continue
            if time.monotonic() - last < self.req.publish_every:
                continue
            last = time.monotonic()
            self.publish_now(None, "live")

    def publish_now(self, frames: Optional[list[int]], state: str):
        from sg3d.graphdb.live import publish

        with self._lock:
            if self.mapper.gravity is None:
                return None
            t0 = time.perf_counter()
            version = self.mapper.version
            # live: the last discovery carried over; the last publish runs discovery itself
            graph, used = self.mapper.graph(frames, scan=self.scan, fast=state == "live")
            self.graph_seconds.append(time.perf_counter() - t0)
            status = {"state": state, "since": self.since, "frames": self.mapper.counts.received,
                      "source": str(self.req.source)}
            report = publish(self.store, graph, self.scan, status, self.embedding, self.fence, self.unseen)
            if self.req.rooms == "auto":
                self._walk_rooms(state)
            self.publish_seconds.append(time.perf_counter() - t0)
            self.published_version = version
            self.publishes += 1
            for i in used:
                if i not in self.latencies and i not in self.mapper.late:   # frames detected live only
                    self.latencies[i] = max(0.0, report.committed_at - self.mapper.source.written_at(i))
            if report.objects and self.first_objects_at is None:
                self.first_objects_at = report.committed_at
            if self.on_update is not None:
                self.on_update({"frames": self.mapper.counts.received, "detected": self.mapper.counts.detected,
                                "objects": report.objects, "created": report.created, "removed": report.removed,
                                "latency_p50": self.latency().get("p50"), "state": state})
            return report

    def _walk_rooms(self, state: str) -> None:
        """The rooms of the walk so far written after a publish (`sg3d.app.places.write_walk_rooms`,
        rooms found again keep their ids and names): live at most every ROOMS_EVERY_S from
        LIVE_FRAMES of the frames so far; the last publish of a recording read whole from its
        frames as a build reads them, so its rooms are the build's."""
        from sg3d.app.places import LIVE_FRAMES, MAX_FRAMES, ROOMS_EVERY_S, Walk, write_walk_rooms
        from sg3d.graphdb.values import room_id

        gravity = self.mapper.gravity
        if gravity is None or (state == "live" and time.monotonic() - self.rooms_at < ROOMS_EVERY_S):
            return
        self.rooms_at = t0 = time.monotonic()
        whole = self.recording if state != "live" and self.recording is not None else None
        frames = whole if whole is not None else self.mapper.source
        n = len(whole) if whole is not None else self.mapper.source.poll()
        walk = Walk(frames, 0, n, gravity.up, gravity.floor_height, most=MAX_FRAMES if whole is not None else LIVE_FRAMES)
        # under the lease, as the publish before it: a map that lost the room writes no rooms either
        self.rooms_found = write_walk_rooms(self.store, room_id(self.req.building, self.req.room), walk, keep=True,
                                            fence=self.fence)
        self.rooms_seconds.append(time.monotonic() - t0)

    def latency(self) -> dict:
        values = np.array(list(self.latencies.values()), float)
        if not values.size:
            return {"n": 0}
        return {"n": int(values.size), "p50": round(float(np.percentile(values, 50)), 3),
                "p95": round(float(np.percentile(values, 95)), 3), "max": round(float(values.max()), 3)}

    def mean_seconds(self) -> float:
        return float(np.mean(self.publish_seconds)) if self.publish_seconds else 0.0


def room_state(store: GraphStore, building: str, room: str) -> dict:
    """One room as `GET /rooms/{building}/{room}` shows it: what `sg3d rooms` lists of it, and
    `mapping`: whether a live map is building it (state live/done, since when, frames so far,
    last publish) or null. NotFound when the room is not in the store."""
    from sg3d.app.errors import NotFound
    from sg3d.app.rooms import list_rooms
    from sg3d.graphdb.live import mapping_status

    known = [r for r in list_rooms(store, building) if r["name"] == room]
    if not known:
        raise NotFound(f"no room {room!r} in building {building!r}")
    status = mapping_status(store, building, room)
    mapping = None
    if status is not None:
        mapping = {"state": status["mapping"], "since": status["since"], "frames": status["frames"],
                   "last_publish": status["updated"], "source": status["source"]}
    return {**known[0], "mapping": mapping}
