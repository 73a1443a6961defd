"""Live mapping (`sg3d map`): the room's local graph kept current while frames arrive.

The paper's framework updates the 3-D scene graph upon new observations. A `LiveMapper` holds
the state a build computes once, and grows it frame by frame:

- frame selection runs online: ABIR (Eq. 1-4) and KGE (Algorithm 1) are causal, so every frame
  is judged the moment it arrives, exactly as a build judges it; KGE's keyframes and anchors are
  detected at once,
  and a sharp frame that shows a new viewpoint (`ONLINE_NEW_VIEW`) is detected too, within the
  build's frame budget so far;
- detection keeps, per detected frame, the detector's boxes, the sightings lifted to 3-D and the
  frame's visibility view (the multi-view evidence fusion and existence need);
- `graph()` recomputes the local graph from that evidence with the build's own functions
  (`pipeline.graph_of_evidence`: fusion, existence, discovery, relations), so a hypothesis that
  later evidence rejects simply is not in the next graph.

Back-pressure: the work is bounded per frame (ABIR + KGE, ~5 ms) and detection takes the newest
chosen frame first; a chosen frame still waiting `MAX_LAG_S` after it was written is skipped
(counted, and detected at the end when the source can read it again), so mapping never falls
behind the camera and the queue never grows without bound.

`finish()` ends a source that can be read again (a folder): gravity is re-estimated the way a
build estimates it, the coverage choice is made over all sharp frames with the build's budget,
the chosen frames not yet detected are detected, and the graph is made of exactly the frames a
build detects: the graph `sg3d build` makes of the same frames.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Optional, Protocol

import numpy as np

from sg3d.core.geometry import horizontal_frame
from sg3d.core.model import LocalGraph, ObjectObservation, ScanInfo
from sg3d.ingest.pipeline import (
    PipelineStats,
    Settings,
    Target,
    detections_of,
    graph_of_evidence,
    sightings_of,
)
from sg3d.ingest.stages import Discovered as Found
from sg3d.ingest.stages import Evidence, Ground, depth_discovery
from sg3d.ingest.detect.models import Detector
from sg3d.ingest.objects import existence, fusion
from sg3d.ingest.poses.gravity import Gravity, estimate_gravity, sample_frames
from sg3d.ingest.poses.online import NotTracked
from sg3d.ingest.readers.frames import Frame, FrameError
from sg3d.ingest.select import coverage
from sg3d.ingest.select.selection import choose_detected_frames

# Live, a sharp frame is detected for its new viewpoint when it lies at least this far (the
# coverage module's viewpoint distance: one unit = 0.3 m or ~14 degrees) from every frame chosen so
# far, within the build's budget so far. The build's own choice (farthest points over the whole
# recording, snapped to the sharpest frame of a window) needs the whole recording: `finish` makes it.
ONLINE_NEW_VIEW = 1.0
# A chosen frame still undetected this long after it was written is skipped while mapping: a
# newer view of the same place is on its way, and the latency goal (objects visible within 2 s
# of their frame) cannot be kept for it anyway.
MAX_LAG_S = 1.5
# Gravity (up and floor) is estimated from this many frames before the first detection: the
# build samples 20 over the whole recording; live, the first 20 (two thirds of a second).
GRAVITY_FRAMES = 20
# Frames waiting to be judged beyond this many (half a second of a 30 Hz camera), mapping jumps
# to the newest: judging what the camera saw a while ago only delays what it sees now. The frames
# jumped over are counted, and `finish` then chooses the build's frames by a whole pass.
MAX_BACKLOG = 15
# A source tracked online (no poses of its own) keeps a tighter budget: tracking comes first, and
# tracking a stale frame only delays the newest one, so mapping jumps to the newest frame when
# more than this many wait (the tracker bridges the gap from a constant-velocity prediction),
# and detection waits while tracking is behind, but runs at least every DETECT_EVERY_S.
TRACKED_BACKLOG = 2
DETECT_EVERY_S = 0.5
# A named object takes the last discovery's verdict on the object of its label this near (a fused
# centre moves by centimetres between two snapshots a few seconds apart).
CARRY_RADIUS_M = 0.3


class LiveSource(Protocol):
    """Where live frames come from (a folder being written, a camera, a stream)."""

    def poll(self) -> int: ...                     # frames complete so far: indices 0..n-1
    def frame(self, i: int) -> Frame: ...          # FrameError: bad or no longer held
    def written_at(self, i: int) -> float: ...     # wall clock (time.time) of frame i's arrival


@dataclass
class Discovered:
    """What the last full discovery found: the nodes from depth (unnamed objects, furniture named
    from shape, structure) and, per named object, (its label and centre before discovery, the
    object after it: renamed from shape, whole box)."""

    nodes: list[ObjectObservation]
    named: list[tuple[str, np.ndarray, ObjectObservation]]
    version: int


def carried_over(objects: list[ObjectObservation], found: Discovered, basis: np.ndarray) -> list[ObjectObservation]:
    """Between two full discoveries (`LiveMapper.graph(fast=True)`): each named object takes the
    verdict the last discovery gave the object of its label nearest to it (within
    CARRY_RADIUS_M: name from shape, whole box), in place; the nodes found from depth come back,
    less those whose centre lies inside a named object's box (named since: not twice)."""
    taken: set[int] = set()
    for k, o in enumerate(objects):
        best, best_d = None, CARRY_RADIUS_M
        for j, (label, centre, after) in enumerate(found.named):
            d = float(np.linalg.norm(np.asarray(o.mean) - centre))
            if label == o.label and j not in taken and d <= best_d:
                best, best_d = j, d
        if best is not None:
            taken.add(best)
            after = found.named[best][2]
            objects[k] = replace(o, labels=list(after.labels), scores=list(after.scores),
                                 size=after.size, box_centre=after.box_centre, named_by=after.named_by,
                                 shape=after.shape)
    boxes = [(basis @ np.asarray(o.box_centre if o.box_centre is not None else o.mean), np.asarray(o.size) / 2)
             for o in objects]
    kept = []
    for n in found.nodes:
        c = basis @ np.asarray(n.box_centre if n.box_centre is not None else n.mean)
        if n.layer == "structure" or not any(np.all(np.abs(c - bc) <= half) for bc, half in boxes):
            kept.append(n)
    return kept


@dataclass
class _Evidence:
    dets: list
    sightings: list
    view: existence.View


@dataclass
class LiveCounts:
    """What live mapping did with the frames (the `--json` summary's "frames")."""

    received: int = 0
    read: int = 0
    blurry: int = 0
    keyframes: int = 0
    anchors: int = 0
    coverage: int = 0            # picked for new viewpoints
    detected: int = 0
    skipped_behind: int = 0      # chosen, but still waiting MAX_LAG_S after arrival
    jumped: int = 0              # never judged live: more than MAX_BACKLOG frames were waiting
    detected_at_end: int = 0     # chosen frames detected by `finish`
    detect_deferred: int = 0     # turns in which detection waited for tracking to catch up
    skipped: dict = field(default_factory=dict)     # frame name -> reason (bad frames)


class LiveMapper:
    """A room's evidence as frames arrive; `look()`, `detect_next()`, `graph()`, `finish()`."""

    def __init__(self, source: LiveSource, detector: Detector, settings: Settings, room: str, building: str,
                 colour_of: Optional[Callable[[int], Optional[np.ndarray]]] = None):
        self.source = source
        self.detector = detector
        self.settings = settings
        self.room, self.building = room, building
        self.params = settings.selection
        selector = self.params.selector()
        self.abir, self.grouper = selector.abir, selector.grouper
        self.colour_of = colour_of or self._colour
        self.counts = LiveCounts()
        self.stats = PipelineStats()
        self.gravity: Optional[Gravity] = None
        self.candidates: list[coverage.Candidate] = []
        self.required: list[int] = []
        self.next_frame = 0                   # next frame to judge (ABIR, KGE)
        self._gravity_frames: list[Frame] = []
        self._queue: dict[int, int] = {}      # frame -> priority (0: keyframe/anchor, 1: coverage)
        self._chosen_views: list[np.ndarray] = []   # viewpoint features of the frames chosen so far
        self._evidence: dict[int, _Evidence] = {}
        self._lock = threading.Lock()
        self.version = 0                      # bumps whenever the evidence changes
        self.late: set[int] = set()           # frames detected by `finish`, after the source ended
        self.discovered: Optional[Discovered] = None
        self.live = True                      # False once the source ended: every frame is judged
        self._last_detect = 0.0               # monotonic time of the last detection
        self._revision = 0                    # the source's pose revision the evidence follows

    # -- frames arriving -----------------------------------------------------------------------
    def look(self, limit: Optional[int] = None) -> int:
        """Judge the frames that arrived since the last call (ABIR, then KGE on the sharp ones),
        at most `limit`; returns how many were judged."""
        self.follow_corrections()
        ready = self.source.poll()
        if self.live and ready - self.next_frame > self.max_backlog():
            self.counts.jumped += ready - 1 - self.next_frame
            self.next_frame = ready - 1
        stop = ready if limit is None else min(ready, self.next_frame + limit)
        n = 0
        for i in range(self.next_frame, stop):
            self._judge(i)
            self.next_frame = i + 1
            n += 1
        # frames that arrived, tracked or not yet: a source tracked online deals with a frame at a
        # time, which on busy cores took 2-4 s (a map that took that for no frame stopped as idle)
        self.counts.received = max(self.counts.received, ready, getattr(self.source, "arrived", 0))
        return n

    def tracked(self) -> bool:
        """Whether the source's poses are tracked online (it carries none of its own)."""
        return getattr(self.source, "posed", True) is False

    def max_backlog(self) -> int:
        """Frames that may wait before mapping jumps to the newest (`MAX_BACKLOG`, or
        `TRACKED_BACKLOG` for a source tracked online)."""
        return TRACKED_BACKLOG if self.tracked() else MAX_BACKLOG

    def may_detect(self) -> bool:
        """Whether detection may run now: always for a source with poses; for one tracked online
        only when tracking is not behind (at most `TRACKED_BACKLOG` frames wait) or the last
        detection is `DETECT_EVERY_S` old (under load the map gets coarser, never stuck)."""
        if not self.tracked() or not self.live or self.backlog() <= TRACKED_BACKLOG:
            return True
        if time.monotonic() - self._last_detect >= DETECT_EVERY_S:
            return True
        self.counts.detect_deferred += 1
        return False

    def backlog(self) -> int:
        """Frames that arrived and were not judged yet."""
        return max(0, self.source.poll() - self.next_frame)

    def _judge(self, i: int) -> None:
        try:
            frame = self.source.frame(i)
            decision = self.abir.update(frame)
            self.counts.read += 1
            if decision.blurry:
                self.counts.blurry += 1
                frame.release()
                return
            role = self.grouper.add(frame)
        except NotTracked:
            self.counts.jumped += 1          # tracking took a newer frame: skipped, not bad
            return
        except FrameError as exc:
            self.counts.skipped[exc.name] = exc.reason
            return
        self.candidates.append(coverage.Candidate(frame.index, frame.pose, decision.variance))
        self._keep(frame)
        if role in ("keyframe", "anchor"):
            self.required.append(frame.index)
            if role == "keyframe":
                self.counts.keyframes += 1
            else:
                self.counts.anchors += 1
            self._chosen_views.append(coverage.viewpoint_features([frame.pose])[0])
            self._queue[frame.index] = 0
        elif self._new_viewpoint(frame):
            self._queue[frame.index] = 1
        if self.gravity is None and len(self._gravity_frames) < GRAVITY_FRAMES:
            self._gravity_frames.append(frame)
        else:
            frame.release()
        self.grouper.completed.clear()        # groups matter to a build's reports only
        if self.gravity is None and len(self._gravity_frames) >= GRAVITY_FRAMES:
            self._estimate_gravity()

    def _keep(self, frame: Frame) -> None:
        """A sharp frame judged is kept by a source that forgets its frames (a camera's ring:
        `keep`), so the end of the map can still detect it (`finish`: the coverage choice over
        every judged frame)."""
        keep = getattr(self.source, "keep", None)
        if keep is not None:
            try:
                keep(frame)
            except FrameError as exc:
                self.counts.skipped.setdefault(exc.name, exc.reason)

    def follow_corrections(self) -> None:
        """When the source's poses were corrected (loop closure of online tracking: its `revision`
        moved on), move the evidence with them: each detected frame's sightings and visibility
        view by the frame's correction (`Sighting.moved`), and the judged frames' poses the
        frame choice uses, so the next graph is made from the corrected poses."""
        revision = getattr(self.source, "revision", 0)
        if revision == self._revision or self.gravity is None:
            return
        self._revision = revision
        pose_of = self.source.pose_of  # type: ignore[attr-defined]  # a source whose poses move (a revision)
        basis = horizontal_frame(self.gravity.up)
        with self._lock:
            for i, ev in list(self._evidence.items()):
                pose = pose_of(i)
                if pose is None or np.allclose(pose, ev.view.pose, atol=1e-4):
                    continue
                move = pose @ np.linalg.inv(ev.view.pose)
                self._evidence[i] = _Evidence(ev.dets, [s.moved(move, basis) for s in ev.sightings],
                                              replace(ev.view, pose=pose))
            self.version += 1
        self.candidates = [replace(c, pose=p) if (p := pose_of(c.index)) is not None else c for c in self.candidates]

    def _estimate_gravity(self, wait_for_more: bool = True) -> None:
        """Gravity from the frames kept for it (then released); when their depth gives none,
        `wait_for_more` drops the older half to make room for newer frames."""
        try:
            self.gravity = estimate_gravity(self._gravity_frames)
        except ValueError:
            if wait_for_more:
                self._gravity_frames = self._gravity_frames[GRAVITY_FRAMES // 2:]   # no depth yet: wait
            return
        for f in self._gravity_frames:
            f.release()
        self._gravity_frames = []

    def _new_viewpoint(self, frame: Frame) -> bool:
        """Whether a sharp frame is detected for its viewpoint (`ONLINE_NEW_VIEW`, within the
        build's budget so far); its viewpoint joins the chosen ones when it is."""
        feat = coverage.viewpoint_features([frame.pose])[0]
        if self._chosen_views:
            nearest = float(np.min(np.linalg.norm(np.asarray(self._chosen_views) - feat, axis=1)))
            budget = coverage.frame_budget(len(self.candidates), self.params.detect_fraction,
                                           self.params.min_detect_frames)
            if nearest < ONLINE_NEW_VIEW or len(self._chosen_views) >= budget:
                return False
        self._chosen_views.append(feat)
        return True

    # -- detection -------------------------------------------------------------------------------
    def pending(self) -> int:
        return len(self._queue)

    def detect_next(self, now: Optional[float] = None) -> bool:
        """Detect the most urgent chosen frame (keyframes and anchors first, newest first); frames
        waiting longer than MAX_LAG_S are skipped first. False when nothing could be detected."""
        if self.gravity is None:
            if self._gravity_frames and self.backlog() == 0 and self._queue:
                self._estimate_gravity(wait_for_more=False)   # a short source: the frames there are
            if self.gravity is None:
                return False
        now = time.time() if now is None else now
        for i in [i for i in self._queue if now - self.source.written_at(i) > MAX_LAG_S]:
            del self._queue[i]
            self.counts.skipped_behind += 1
        if not self._queue:
            return False
        i = min(self._queue, key=lambda k: (self._queue[k], -k))
        priority = self._queue.pop(i)
        self._last_detect = time.monotonic()
        if self._detect(i) and priority == 1:
            self.counts.coverage += 1
        return True

    def _detect(self, i: int) -> bool:
        assert self.gravity is not None
        try:
            frame = self.source.frame(i)
            frame.load()
        except FrameError as exc:
            self.counts.skipped[exc.name] = exc.reason
            return False
        dets = detections_of(frame, self.detector, self.settings, self.stats)
        found = sightings_of(frame, dets, Ground(self.gravity.up, self.gravity.floor_height), self.stats)
        ev = _Evidence(dets, found, existence.View.of(frame))
        frame.release()
        with self._lock:
            self._evidence[i] = ev
            self.version += 1
        self.counts.detected += 1
        return True

    def skipped(self, seq: Any = None) -> dict[str, str]:
        """Frame name -> reason of every bad frame met: those this mapper met, and (with `seq`, the
        recording it followed) those its reader met anywhere else (gravity, a whole-recording
        pass, the motion check), as a build names them."""
        out = dict(self.counts.skipped)
        for name, reason in (seq.skipped if seq is not None else []):
            out.setdefault(name, reason)
        return out

    def detected_frames(self) -> list[int]:
        with self._lock:
            return sorted(self._evidence)

    # -- the graph -------------------------------------------------------------------------------
    def graph(self, frames: Optional[list[int]] = None, scan: Optional[ScanInfo] = None,
              stats: Optional[PipelineStats] = None, fast: bool = False) -> tuple[LocalGraph, list[int]]:
        """The local graph of the evidence so far (or of `frames` among it) and the frames it was
        made of; safe to call from another thread while frames are detected. `fast`: discovery
        from depth is not run again, the last one's findings are carried over (`carried_over`);
        without it the discovery runs and is kept for the fast graphs that follow."""
        assert self.gravity is not None
        with self._lock:
            chosen = sorted(self._evidence) if frames is None else [i for i in frames if i in self._evidence]
            evidence = [self._evidence[i] for i in chosen]
            version = self.version
        sightings: list[fusion.Sighting] = [s for ev in evidence for s in ev.sightings]
        views = [ev.view for ev in evidence]
        found = self.discovered
        if fast and found is not None:
            basis = horizontal_frame(self.gravity.up)

            def discover(evidence: Evidence, objects: list[ObjectObservation]) -> Found:
                return Found(objects=carried_over(objects, found, basis))
        elif fast:
            def discover(evidence: Evidence, objects: list[ObjectObservation]) -> Found:
                return Found(objects=[])
        else:
            def discover(evidence: Evidence, objects: list[ObjectObservation]) -> Found:
                before = [(o.label, np.asarray(o.mean, float)) for o in objects]
                result = depth_discovery(self.settings)(evidence, objects)
                self.discovered = Discovered(list(result.objects), [(label, centre, after) for (label, centre), after
                                                                    in zip(before, objects)], version)
                return result
        seen = Evidence(sightings, views, self.colour_of, Ground(self.gravity.up, self.gravity.floor_height))
        graph = graph_of_evidence(seen, Target(self.room, self.building, scan=scan), self.settings,
                                  stats or PipelineStats(), discover=discover)
        return graph, chosen

    def _colour(self, i: int) -> Optional[np.ndarray]:
        try:
            return self.source.frame(i).color
        except FrameError:
            return None

    # -- the end of the source -------------------------------------------------------------------
    def finish(self, seq: Any = None) -> list[int]:
        """The source ended: judge what is left, then (when `seq`, the whole recording, can be read
        again) make the evidence a build's: gravity as a build estimates it (sightings measured
        again under it when it differs), the coverage choice over all sharp frames, the chosen
        frames not yet detected detected now. Returns the frames the final graph is made of."""
        self.live = False
        self.follow_corrections()
        while self.look():
            pass
        if seq is not None and self.counts.jumped:
            # frames were jumped over live: the build's choice needs a whole pass of ABIR and KGE
            choice = choose_detected_frames(seq, 0, len(seq), params=self.params)
            final, self.required = choice.detected, choice.required
        else:
            budget = coverage.recording_budget(len(self.candidates), self.counts.read, self.counts.received,
                                               self.params.detect_fraction, self.params.min_detect_frames)
            final = coverage.choose_frames(self.candidates, self.required, budget)
        if seq is not None and len(seq):
            try:     # gravity as a build estimates it; the sightings follow it
                built: Optional[Gravity] = estimate_gravity(sample_frames(seq, 20, 0, len(seq)))
            except ValueError:
                built = None
            if built is not None and (self.gravity is None or (built.up, built.floor_height)
                                      != (self.gravity.up, self.gravity.floor_height)):
                self.gravity = built
                self._measure_again(final)
        if self.gravity is None and self._gravity_frames:
            self._estimate_gravity(wait_for_more=False)   # a short source: the frames there are
        if self.gravity is None:
            return []
        for i in final:
            if i not in self._evidence and self._detect(i):
                self.late.add(i)
                self.counts.detected_at_end += 1
        self.counts.coverage = len(final) - len(set(self.required))
        return final

    def _measure_again(self, frames: list[int]) -> None:
        """Sightings of `frames` lifted to 3-D again under the current gravity (the detector's
        boxes are kept; attributes depend on the up direction)."""
        assert self.gravity is not None
        up = self.gravity.up
        for i in frames:
            ev = self._evidence.get(i)
            if ev is None:
                continue
            try:
                frame = self.source.frame(i)
                frame.load()
            except FrameError:
                continue
            found = sightings_of(frame, ev.dets, Ground(up, self.gravity.floor_height), self.stats)
            frame.release()
            with self._lock:
                self._evidence[i] = _Evidence(ev.dets, found, ev.view)
                self.version += 1
