"""Loop closure for online tracking (`sg3d.ingest.poses.online.OnlinePoses`), off the tracking path.

Tracking chains frame-to-keyframe motions, so its error grows with the path (the kitchen's 1,000
frames drift ~40 cm). A `LoopCloser` runs on a thread of its own at a lower CPU priority
(`NICE`), and only while tracking waits for a frame (`may_run`: a lower CPU priority does not keep
its Python from holding the interpreter lock: closing loops beside a busy tracker slowed a kitchen
frame from 109 to 169 ms at a load of 10), and does what the offline
estimate does (`sg3d.ingest.poses.closure`, `sg3d.ingest.poses.graph`):

- tracking offers it a keyframe every `estimate.KEYFRAME_M` / `estimate.KEYFRAME_DEG` (the offline
  spacing) with the chained motion from the previous one (an odometry edge);
- each is fitted to the keyframes before it (`neighbour_edges`) and to older ones it comes back
  near (`loop_edges`), with an odometry of its own (OpenCV's is not shared between threads);
- after a new loop closure, and every `OPTIMISE_EVERY` keyframes, the pose graph is optimised
  (GTSAM) and tracking applies the correction to every placed frame (`OnlinePoses.correct`):
  each frame moves with the loop keyframe it was placed after.

Memory: the reduced depth and grey image of each loop keyframe (~0.4 MB at 320x240, ~100 for the
kitchen's 1,000 frames); a candidate's odometry pyramids are made again when it is fitted.
"""
from __future__ import annotations

import os
import threading
from collections import deque
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from sg3d.ingest.poses.closure import Edge, loop_edges, neighbour_edges
from sg3d.ingest.poses.graph import optimise_pose_graph
from sg3d.ingest.poses.tracking import Odometry, View

NICE = 10                    # the closer's CPU priority below tracking's (Linux threads; 0 elsewhere)
OPTIMISE_EVERY = 10          # loop keyframes between optimisations when no loop was closed
IDLE_POLL_S = 0.02           # how often a closer waiting for tracking to be idle looks again


@dataclass
class _Offer:
    index: int
    depth: np.ndarray
    gray: np.ndarray
    edge: Optional[Edge]         # from the previous loop keyframe (None for the first)


Snapshot = Callable[[list[int]], dict[int, np.ndarray]]
Correct = Callable[[dict[int, np.ndarray], dict[int, np.ndarray]], None]


class LoopCloser:
    """Keyframes offered by tracking, closed into a pose graph on a low-priority thread (module doc).
    `snapshot(indices)` gives the current poses of those frames; `correct(before, after)` moves
    the placed frames from the `before` poses of the loop keyframes to the optimised `after`."""

    def __init__(self, odometry: Odometry, snapshot: Snapshot, correct: Correct,
                 may_run: Callable[[], bool] = lambda: True):
        self.odometry = odometry
        self.snapshot, self.correct, self.may_run = snapshot, correct, may_run
        self.views: list[View] = []
        self.edges: list[Edge] = []
        self.loops = 0
        self.optimisations = 0
        self._queue: deque[_Offer] = deque()
        self._wake = threading.Event()
        self._stop = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self._since_optimised = 0
        self.error: Optional[BaseException] = None

    def offer(self, index: int, depth: np.ndarray, gray: np.ndarray, edge: Optional[Edge]) -> None:
        """A new loop keyframe (tracking's reduced depth and grey image) and its odometry edge."""
        self._queue.append(_Offer(index, depth, gray, edge))
        self._wake.set()

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="sg3d-map-loops", daemon=True)
        self._thread.start()

    def stop(self, drain: bool = True) -> None:
        """End the thread; with `drain`, close the keyframes still waiting first (the source
        ended: the cores are free) and optimise once more."""
        self._stop.set()
        self._wake.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None
        if self.error is not None:
            raise self.error
        if drain:
            while self._queue:
                self._close(self._queue.popleft())
            if self._since_optimised:
                self._optimise()

    def _run(self) -> None:
        try:
            lower_thread_priority(NICE)
            while not self._stop.is_set():
                if not self._queue or not self.may_run():
                    self._wake.wait(IDLE_POLL_S)
                    self._wake.clear()
                    continue
                self._close(self._queue.popleft())
        except Exception as exc:   # noqa: BLE001 - raised again by stop() on the caller's thread
            self.error = exc

    def _close(self, offer: _Offer) -> None:
        """Fit one loop keyframe to its neighbours and to older keyframes near it; optimise after
        a loop closure or every `OPTIMISE_EVERY` keyframes."""
        try:
            view = self.odometry.view(offer.index, offer.depth, offer.gray)
        except ValueError:
            return
        if offer.edge is not None:
            self.edges.append(offer.edge)
        poses = self.snapshot([v.index for v in self.views] + [view.index])
        found = neighbour_edges(self.odometry, view, poses, self.views) if self.views else []
        loops = loop_edges(self.odometry, view, poses, self.views)
        self.edges.extend(found + loops)
        self.loops += len(loops)
        self.views.append(view)
        self._since_optimised += 1
        if loops or self._since_optimised >= OPTIMISE_EVERY:
            self._optimise()

    def _optimise(self) -> None:
        nodes = [v.index for v in self.views]
        if len(nodes) < 2:
            return
        before = self.snapshot(nodes)
        known = set(before)
        edges = [e for e in self.edges if e[0] in known and e[1] in known]
        after = optimise_pose_graph(before, edges, anchor=nodes[0])
        self.correct(before, after)
        self.optimisations += 1
        self._since_optimised = 0


def lower_thread_priority(nice: int) -> None:
    """The calling thread at `nice` below the process (Linux gives threads their own nice value;
    elsewhere the thread keeps the process's priority). For threads that end with their work:
    a thread cannot take its priority back."""
    try:
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), os.getpriority(os.PRIO_PROCESS, 0) + nice)
    except (AttributeError, OSError):   # another system: the thread runs at the process's priority
        pass
