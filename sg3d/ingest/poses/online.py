"""Poses for a live source that has none (a RealSense camera, an MCAP recording without /tf or
odometry): RGB-D odometry as the frames arrive (`sg3d map realsense`).

`OnlinePoses` wraps a `sg3d.ingest.live.LiveSource` whose frames carry no pose (a NaN matrix)
and gives each frame, the first time it is read, a camera-to-world pose (world = the first
tracked camera; the live mapper estimates up and floor from the frames themselves):

- the frame is fitted to the last keyframe (`Odometry.fit`, trust check: `TRACK_MIN_INLIERS`
  of its depth confirmed), and its pose is the keyframe's pose chained with that motion; a fit
  confirming less than `TRACK_TRUST` gets a second opinion (a depth-only fit to the keyframe, a
  fit to the last placed frame, and, when all confirm less, a fit to the keyframe from the
  constant-velocity prediction) and the fit confirming most is taken;
  it becomes the next keyframe when it lies `KEYFRAME_M` / `KEYFRAME_DEG` away from the last one
  or shows less than `KEYFRAME_INLIERS` in common with it (drift grows per keyframe, not per
  frame);
- after a gap (frames never tracked: a camera dropping them, or a mapper that skipped ahead to
  the newest frame to keep up), the fit to the last keyframe starts from a constant-velocity
  prediction (`predict_pose`: the motion of the last `VELOCITY_WINDOW_S` carried on to the new
  frame's time), which OpenCV's odometry cannot take as a guess but `Odometry.fit_from` can;
- when that fit fails, the frame is fitted to the last placed frame; then a frame in between is
  tracked first (`_fill_gap`, as the offline estimate tries the frames in between: the living
  room's first frames move 2 cm each, before any prediction exists); then it is re-localised against
  `RELOCALISE_TRIES` older keyframes, starting from the predicted pose (else the last known one;
  `Odometry.fit_from`), as far as `LOSS_BUDGET_S` allows after the bridges;
- a frame none of them places is skipped with the reason "lost track: ..." (`FrameError`, so
  the mapper lists it and goes on); the next placeable frame continues from the last known pose.
  After `MAX_LOST` unplaceable frames in a row (that still show enough depth), `MAX_LOST_S`
  after the last placed one, the track restarts:
  the next such frame becomes a keyframe at the last known pose (counted in `restarts`).

Loop closure runs off the tracking path (`sg3d.ingest.poses.live_loops.LoopCloser`, the offline
estimate's closures and GTSAM pose graph): every `LOOP_KEYFRAME_M` / `LOOP_KEYFRAME_DEG` a keyframe
is offered to it, and an optimised graph moves every placed frame with the loop keyframe it was
placed after (`correct`; `revision` counts the corrections, `pose_of` gives a frame's pose now, and
the live mapper moves its evidence with them).

A frame that already carries a finite pose passes through untouched, and so does every frame of
a source that says it carries poses (`posed` True: a folder with pose files). A source that can
be read again (a folder, with or without poses) is read again at the end as a build reads it
(`seq`, `whole()`): a pose-less one with the poses tracked live, the frames tracking went past
interpolated between them, so the last graph is made of the frames a build detects however few
frames tracking could afford (a camera's is made of the frames tracked live). Odometry runs at about 320
px width (`sg3d.ingest.poses.tracking`): 15-40 ms a frame on 2 cores. Memory: a pose per frame
(128 bytes) and the reduced views of the recent keyframes.
"""
from __future__ import annotations

import threading
import time
from collections import deque
from typing import Any, Optional

import numpy as np

from sg3d.ingest.poses.estimate import KEYFRAME_DEG as LOOP_KEYFRAME_DEG
from sg3d.ingest.poses.estimate import KEYFRAME_M as LOOP_KEYFRAME_M
from sg3d.ingest.poses.live_loops import LoopCloser
from sg3d.ingest.poses.sequence import DepthCameraImages
from sg3d.ingest.poses.tracking import Fit, Odometry, View, motion_gap
from sg3d.ingest.poses.trajectory import interpolate_poses
from sg3d.ingest.readers.frames import Frame, FrameError

# Odometry runs on images this wide (320x240 from 640x480). Measured on the kitchen on 2 busy
# cores: at 160 px a fit costs ~4x less (23 against 104 ms), but every 5th of the first 300 frames
# gave ATE 6.8 cm against 3.7 cm and a gap of 20 frames was no longer bridged.
ONLINE_WIDTH = 320
TRACK_MIN_INLIERS = 0.5      # share of a frame's depth the keyframe must confirm (as `estimate`)
TRACK_TRUST = 0.85           # a fit confirming less gets a second opinion (`_fit`): on the kitchen, RGB-D
                             # fits to a keyframe 6-9 frames back that confirmed 0.65-0.8 slid 4-14 cm
                             # (the true motion confirms 0.8-0.9), fits 2-3 frames apart confirm 0.9+
TRACK_IMAGE_NCC = 0.93      # a fit's images agree at least this much (`image_agreement`): kitchen fits within
                             # 2 cm of the given motion agreed 0.94-0.95 at their 1st percentile, those 7-31 cm
                             # off 0.74-0.93 but for one in 15 (0.966)
KEYFRAME_M, KEYFRAME_DEG = 0.05, 5.0   # measured on the kitchen: 0.05 m / 5 deg ATE 6 mm, 0.1 m / 10 deg 37 mm
KEYFRAME_INLIERS = 0.7       # a frame sharing less than this with the keyframe becomes the next one
RELOCALISE_KEYFRAMES = 5     # recent keyframes held for relocalisation
RELOCALISE_TRIES = 2         # older keyframes a lost frame is tried against (the time budget of a loss:
RELOCALISE_ROUNDS = 2        # each try is up to this many fits from a guess, ~55 ms each)
RELOCALISE_OVERLAP, RELOCALISE_AGREEMENT = 0.4, 0.8
MAX_LOST = 2                 # unplaceable frames in a row before the track restarts at the last pose,
MAX_LOST_S = 0.7             # and at least this long without a pose: never lost for much more than this
                             # (a restart's frame is offered to loop closure, which can place it again
                             # against the keyframes around)
LOSS_BUDGET_S = 0.3          # tracking time a frame may take in frames in between and relocalising after
                             # the bridges from the prediction failed (at a load of 9, ten fits from a guess took 2-3 s a
                             # frame: three lost frames kept the track lost for 4.8 s)
VELOCITY_WINDOW_S = 0.3      # the camera's velocity: its motion over about this long before the last frame
TRACK_POLL_S = 0.01          # how often the tracking thread looks for a new frame
HELD_FRAMES = 4              # decoded frames kept for the mapper after tracking (a few turns' worth)
MAX_PREDICT_S = 1.5          # no prediction further ahead than this (a camera may have stopped)
GAP_FILLS = 3                # frames in between a frame that could not be placed may read (`_fill_gap`)
TRACK_STRIDE_S = 0.2         # the longest step between the frames tracking takes while it catches up: the
                             # kitchen live at 30 frames/s on 2 busy cores, tracking stalled 18-31 times for
                             # 0.3-0.8 s; jumping to the newest frame after each (12-25 frames) gave ATE
                             # 8.7-13.2 cm, the same frames replayed with steps of at most 6 frames 2.8-3.1 cm
MAX_TRACK_LAG_S = 1.5        # further behind than this tracking jumps to the newest frame (latency first)
FRAME_PERIOD_S = 1 / 30      # a frame's time before two frames were placed (the common camera rate)
BRIDGE_ROUNDS = 3            # fits from a guess, each starting where the last ended (measured: a guess
                             # 3.5 cm / 4.8 deg off converged in the second round, not the first)


def _left_jacobian(w: np.ndarray) -> np.ndarray:
    """SO(3)'s left Jacobian of a rotation vector: maps the screw's translation rate to the
    translation it gives (I + (1 - cos a)/a^2 W + (a - sin a)/a^3 W^2)."""
    a = float(np.linalg.norm(w))
    W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    if a < 1e-9:
        return np.eye(3) + W / 2
    return np.eye(3) + (1 - np.cos(a)) / a**2 * W + (a - np.sin(a)) / a**3 * W @ W


def screw_power(V: np.ndarray, f: float) -> np.ndarray:
    """V^f for a rigid motion V: the same screw motion (rotation about and translation along one
    axis) carried on `f` times as far (closed form of expm(f logm(V)); scipy's logm costs ~100x more)."""
    from scipy.spatial.transform import Rotation

    w = Rotation.from_matrix(V[:3, :3]).as_rotvec()
    u = np.linalg.solve(_left_jacobian(w), V[:3, 3])
    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(w * f).as_matrix()
    out[:3, 3] = _left_jacobian(w * f) @ (u * f)
    return out


def predict_pose(history: list[tuple[float, np.ndarray]], t: float) -> Optional[np.ndarray]:
    """Constant-velocity prediction of the camera-to-world pose at time `t` from the placed poses
    `history` [(time, pose), ...] (oldest first): the relative motion between the last pose and
    the oldest one at most `VELOCITY_WINDOW_S` before it, carried on to `t` (`screw_power`); None with fewer than two poses, no time between them, or `t`
    more than `MAX_PREDICT_S` after the last."""
    if len(history) < 2:
        return None
    t_last, last = history[-1]
    t_ref, ref = next(((ti, P) for ti, P in history[:-1] if t_last - ti <= VELOCITY_WINDOW_S), history[-2])
    dt = t_last - t_ref
    if dt <= 0 or not 0 <= t - t_last <= MAX_PREDICT_S:
        return None
    V = np.linalg.inv(ref) @ last                 # the motion over dt, in the last camera's frame
    return last @ screw_power(V, (t - t_last) / dt)


def next_to_track(next_frame: int, arrived: int, present: int, stride: int, max_lag: int) -> int:
    """Rule "a recording's every frame, a camera's frames in reach of a fit": the frame tracking
    takes next when `arrived` frames are there and frames before `next_frame` were dealt with.
    The frames the source already held when mapping started (`present`: a folder written before,
    or while a map was not running) are a recording nobody waits for, tracked in order as a build
    would. Past them tracking steps at most `stride` frames past the last one it took (a fit
    bridges the motion of a few tenths of a second; a jump over a stall of the machine does not):
    behind the newest frame it catches up in such steps, and jumps to the newest only when
    that is more than `max_lag` frames ahead of the step (the map stays live, and a camera's ring
    still holds the frames stepped to)."""
    if next_frame < present:
        return next_frame
    newest = arrived - 1
    if next_frame == 0:
        return newest
    step = next_frame - 1 + max(1, stride)
    return newest if newest - step > max_lag else min(newest, step)


def track_steps(period_s: float, ring: Optional[int]) -> tuple[int, int]:
    """(stride, max_lag) of `next_to_track` in frames for frames `period_s` apart: `TRACK_STRIDE_S`
    and `MAX_TRACK_LAG_S` of the recording's time, the lag no more than half of a source's
    `ring` (the frames a camera holds; the ring moves on while tracking steps through it)."""
    stride = max(1, int(round(TRACK_STRIDE_S / period_s)))
    lag = int(round(MAX_TRACK_LAG_S / period_s))
    return stride, lag if ring is None else min(lag, ring // 2)


def filled_poses(placed: dict[int, np.ndarray], times: list[float], unplaced: set[int]) -> dict[int, np.ndarray]:
    """A pose for every frame 0..len(times)-1 between the first and the last `placed` one but those
    in `unplaced`: placed frames keep theirs, the others are interpolated by their timestamps
    between the placed ones around them (`trajectory.interpolate_poses`: translation linear in
    time, rotation by Slerp)."""
    known: list[int] = []
    for i in sorted(i for i in placed if i < len(times)):
        if not known or times[i] > times[known[-1]]:      # Slerp needs increasing times
            known.append(i)
    if not known:
        return {}
    between = [k for k in range(known[0], known[-1] + 1) if k not in unplaced or k in placed]
    poses = interpolate_poses([times[i] for i in known], np.array([placed[i] for i in known]),
                              [times[k] for k in between])
    out = dict(zip(between, poses))
    out.update({i: placed[i].copy() for i in placed if i in out})
    return out


class NotTracked(FrameError):
    """A frame tracking went past (it took a newer one): not a bad frame, a skipped one."""


class OnlinePoses:
    """A `LiveSource` that gives the frames of a pose-less one a pose by odometry (module doc)."""

    def __init__(self, source: Any, max_depth: float = 4.0) -> None:
        self.source = source
        self.max_depth = max_depth
        self.poses: dict[int, np.ndarray] = {}
        self.times: dict[int, float] = {}             # frame -> its timestamp (placed frames)
        self.lost: dict[int, str] = {}                # frame -> reason (the source's own FrameErrors too)
        self.tracked = 0
        self.restarts = 0
        self._names: dict[int, str] = {}
        self._next = 0                                # next frame to track
        self._odometry: Optional[Odometry] = None
        self._keyframes: deque[View] = deque(maxlen=RELOCALISE_KEYFRAMES)
        self._last: Optional[View] = None             # the last placed frame
        self._lost_in_row = 0
        self._history: deque[tuple[float, np.ndarray]] = deque(maxlen=16)   # (time, pose) of placed frames
        self._held: dict[int, Frame] = {}             # frames tracked last (decoded once for both uses)
        self._lock = threading.Lock()
        self._thread: Optional[threading.Thread] = None
        self._stop = threading.Event()
        self._idle = threading.Event()                # the tracking thread waits for a frame (loop closure may run)
        self._ready = 0                               # frames the tracking thread has dealt with
        self._present: Optional[int] = None           # frames the source already held when it was first polled
        self.arrived = 0                              # frames the source holds (tracking may be a few behind)
        self.error: Optional[BaseException] = None
        self.seconds: deque[float] = deque(maxlen=10_000)   # per frame the tracking thread took (read + fit)
        self._closer: Optional[LoopCloser] = None
        self._images: Optional[DepthCameraImages] = None   # a recording on disk: odometry's own images
        self._anchor: dict[int, int] = {}             # placed frame -> the loop keyframe it was placed after
        self._loop_last: Optional[int] = None         # the newest loop keyframe
        self.revision = 0                             # bumps whenever loop closure moved the placed frames
        self.filled: dict[int, np.ndarray] = {}       # the source ended: every frame's pose (`whole`)

    # -- tracking on its own thread ------------------------------------------------------------------
    def start(self) -> None:
        """Track on a thread of its own from now on: past the frames the source held when first
        polled (tracked in order) it takes the newest frame that arrived, or, when it fell behind,
        a frame at most `TRACK_STRIDE_S` past the last one it took (`next_to_track`; the frames
        in between are never tracked: `NotTracked`), so tracking keeps up with the camera
        whatever detection and publishing cost, in steps a fit bridges (`_fit`); `poll()` then
        says how many frames tracking has dealt with. A source with poses stops the thread."""
        self._thread = threading.Thread(target=self._follow, name="sg3d-map-track", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop tracking; the loop keyframes still waiting are closed and the graph optimised once
        more (the source ended), so the poses read from now on are the corrected ones."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None
        if self.error is not None:
            raise self.error
        self.close_loops()

    def close_loops(self) -> None:
        """Close the loop keyframes offered so far (and stop the closer's thread, if running)."""
        if self._closer is not None:
            self._closer.stop(drain=True)

    def _follow(self) -> None:
        try:
            while not self._stop.is_set():
                with self._lock:
                    n = self.source.poll()
                    self.arrived = n
                    if self.posed:
                        return                        # nothing to track: poll() passes through
                    if self._present is None and n:
                        self._present = n
                    fresh = n - 1 >= self._next
                    if fresh:
                        self._idle.clear()
                        t0 = time.perf_counter()
                        i = next_to_track(self._next, n, self._present or 0,
                                          *track_steps(self._frame_period(), getattr(self.source, "ring", None)))
                        self._track(i)
                        self._next = i + 1
                        self.seconds.append(time.perf_counter() - t0)
                    self._ready = self._next
                if not fresh:
                    self._idle.set()
                    self._stop.wait(TRACK_POLL_S)
        except Exception as exc:   # noqa: BLE001 - raised again on the mapping thread by stop()
            self.error = exc

    def _frame_period(self) -> float:
        """Seconds between two frames of the source, by the timestamps of the first and the last
        placed frame (`FRAME_PERIOD_S` before there are two)."""
        if len(self.poses) < 2:
            return FRAME_PERIOD_S
        first, last = min(self.times), max(self.times)
        span = self.times[last] - self.times[first]
        return span / (last - first) if span > 0 and last > first else FRAME_PERIOD_S

    # -- the LiveSource protocol ------------------------------------------------------------------
    @property
    def posed(self) -> bool:
        """Whether the source carries its own poses (then nothing is tracked)."""
        return getattr(self.source, "posed", False) is True

    @property
    def seq(self) -> Any:
        """The recording to read again at the end (a folder: with or without poses of its own);
        None for a source that cannot be read again (a camera, a stream)."""
        return getattr(self.source, "seq", None)

    def whole(self) -> Any:
        """The recording as a build reads it, once the source ended (None when it cannot be read
        again): with its own poses, or, pose-less, with the poses tracked live (`filled_poses`:
        the frames tracking went past take poses interpolated between the placed ones, as the
        offline estimate fills the frames between its tracked ones), so the mapper can catch up
        on the frames a build would detect (`LiveMapper.finish`)."""
        if self.posed:
            return self.source.whole()
        seq = self.source.whole() if hasattr(self.source, "whole") else None
        if seq is None:
            return None
        times = [seq.timestamp_of(i) for i in range(len(seq))]
        self.filled = filled_poses(self.poses, times, set(self.lost))
        unplaced = {i: self.lost.get(i, "not placed: outside the frames tracked live")
                    for i in range(len(seq)) if i not in self.filled}
        seq.use_poses(self.filled, unplaced)
        return seq

    @property
    def waiting_for(self) -> str:
        return getattr(self.source, "waiting_for", "the first frames")

    def poll(self) -> int:
        if self._stop.is_set() and not self.posed:
            return self._ready                        # stopped: what tracking dealt with, no more
        if self._thread is None or self.posed:
            with self._lock:
                return self.source.poll()
        return self._ready

    def written_at(self, i: int) -> float:
        return self.source.written_at(i)

    @property
    def keep(self) -> Optional[Any]:
        """The source's `keep` (frames kept past a camera's ring), None when it has none."""
        return getattr(self.source, "keep", None)

    def pose_of(self, i: int) -> Optional[np.ndarray]:
        """Frame i's current pose (loop closure moves placed frames: `revision`), None if unplaced."""
        pose = self.poses.get(i)
        return None if pose is None else pose.copy()

    def frame(self, i: int) -> Frame:
        """Frame i with its pose, tracked from the last placed frame when i is new (frames the mapper
        jumped over while behind are not tracked); FrameError "lost track: ..." when odometry could
        not place it."""
        if self.posed:
            return self.source.frame(i)
        if self._thread is None:
            with self._lock:
                if i >= self._next:          # frames the mapper jumped over are never tracked
                    self._track(i)
                    self._next = i + 1
        if i in self.lost:
            raise FrameError(self._names.get(i, f"frame {i}"), self.lost[i])
        held = self._held.pop(i, None)
        frame = held if held is not None else self.source.frame(i)
        pose = self.poses.get(i, self.filled.get(i))
        if pose is None:
            if np.all(np.isfinite(frame.pose)):
                return frame                             # it carries its own pose
            raise NotTracked(frame.name, "not tracked: tracking went past it to a newer frame")
        frame.pose = pose
        return frame

    # -- tracking ---------------------------------------------------------------------------------
    def _track(self, i: int) -> None:
        try:
            frame = self.source.frame(i)
            self._hold(frame)
            self._names[i] = frame.name
            if np.all(np.isfinite(frame.pose)):
                self.poses[i] = frame.pose
                self.times[i] = frame.timestamp
                return
            self.times[i] = frame.timestamp
            view = self._view(frame)
        except FrameError as exc:
            self._names[i] = exc.name
            self.lost[i] = exc.reason
            return
        except ValueError as exc:                      # too little depth to track
            self._lose(i, f"lost track: {exc}", counts=False)
            return
        self.tracked += 1
        if self._last is None:                         # the first frame: the world's origin
            self._place(view, np.eye(4), keyframe=True)
            return
        placed = self._fit(view)
        if placed is not None:
            self._place_fitted(view, placed)
            return
        lost_for = self.times[view.index] - self.times[self._last.index]
        if self._lost_in_row >= MAX_LOST and lost_for >= MAX_LOST_S:   # a new track from the last known pose
            self.restarts += 1
            self._keyframes.clear()
            self._place(view, self.poses[self._last.index], keyframe=True, restart=True)
            return
        self._lose(i, self._why)

    def _view(self, frame: Frame) -> View:
        """The frame reduced for odometry: in the depth camera's own pixels when the source is a
        camera that gives its depth unaligned with its calibration (`depth_camera`: a RealSense)
        or a recording on disk that says how its depth is registered (`DepthCameraImages`, as
        the offline estimate reads it: registered depth bends the geometry ICP relies on; the
        kitchen's every 2nd frame tracked on its registered depth: ATE 7.2 cm, on the depth
        camera's pixels 3.05 cm), else the frame's colour-registered depth."""
        depth, grey, K, size = frame.depth, frame.gray, frame.K, frame.size
        seq = getattr(self.source, "seq", None)
        own = self.source.depth_camera(frame.index) if hasattr(self.source, "depth_camera") else None
        if own is not None:                            # a camera's depth in its own pixels
            depth, grey, K = own
            size = (depth.shape[1], depth.shape[0])
        elif seq is not None and hasattr(seq, "pixels") and hasattr(seq, "registration"):
            if self._images is None or self._images.seq is not seq:     # a folder listed again
                self._images = DepthCameraImages(seq)
            depth, grey = self._images(frame.index)
            K, size = seq.depth_K, (depth.shape[1], depth.shape[0])
        if self._odometry is None:
            self._odometry = Odometry(K, size, self.max_depth, ONLINE_WIDTH)
            self._closer = LoopCloser(Odometry(K, size, self.max_depth, ONLINE_WIDTH), self._snapshot, self.correct,
                                      self._idle.is_set)
            if self._thread is not None:
                self._closer.start()
        return self._odometry.view(frame.index, depth, grey)

    def _fit(self, view: View, deep: bool = True) -> Optional[tuple[np.ndarray, float]]:
        """(pose, share of its depth confirmed) from the last keyframe (directly; when that fit
        confirms less than `TRACK_TRUST`, the best of it, a fit to the last placed frame and, when
        that confirms less too, a depth-only fit to the keyframe and, still weak, a fit to it from
        the constant-velocity prediction: on the kitchen tracked every 8th frame, direct fits in
        front of the cupboards confirmed 64-83 % and had slid 5-13 cm, ATE 16.7 cm against 4.2
        with it), then from the prediction (to the last placed frame), or the recent keyframes starting
        from the prediction (else the last known pose); None (reason in `_why`). Cheapest first:
        a direct fit costs ~20 ms at 320x240, one from a guess ~55 ms (it renders the view)."""
        assert self._odometry is not None and self._last is not None
        odo = self._odometry
        key = self._keyframes[-1]
        fits = [(odo.fit(view, key, TRACK_MIN_INLIERS), key)]
        if fits[0][0].inliers < TRACK_TRUST and self._last.index != key.index:   # a weak fit: the last frame
            fits.append((odo.fit(view, self._last, TRACK_MIN_INLIERS), self._last))
        if max(f.inliers for f, _ in fits) < TRACK_TRUST:                          # still weak: depth alone
            fits.append((odo.fit_depth(view, key, TRACK_MIN_INLIERS), key))
        # `deep` False (a frame in between, `_fill_gap`): the direct fits only, no fit from a guess
        predicted = predict_pose(list(self._history), self.times[view.index]) if deep else None
        bridged = max(f.inliers for f, _ in fits) < TRACK_TRUST and predicted is not None
        if bridged:                      # still weak: from the constant-velocity prediction
            fits.append((self._bridge(view, key, np.linalg.inv(self.poses[key.index]) @ predicted, TRACK_MIN_INLIERS),
                         key))
        placed = [(f, ref) for f, ref in fits if self._confirmed(f, view, ref)]
        if placed:                                # the fit confirming the most
            best, ref = max(placed, key=lambda fr: fr[0].inliers)
            return self.poses[ref.index] @ best.motion, best.inliers if ref is key else 0.0
        why = f"against keyframe {key.index}: {fits[0][0].why}"
        if predicted is not None:        # a gap or a fast turn: start where the camera should be
            for ref in (key, self._last) if self._last.index != key.index else (key,):
                if ref is key and bridged:
                    continue             # tried above
                fit = self._bridge(view, ref, np.linalg.inv(self.poses[ref.index]) @ predicted, TRACK_MIN_INLIERS)
                if self._confirmed(fit, view, ref):
                    return self.poses[ref.index] @ fit.motion, fit.inliers if ref is key else 0.0
        deadline = time.perf_counter() + LOSS_BUDGET_S     # frames in between, then older keyframes
        filled = self._fill_gap(view, deadline) if deep else None
        if filled is not None or not deep:
            self._why = f"lost track: not placed by odometry ({why})"
            return filled
        start = predicted if predicted is not None else self.poses[self._last.index]
        for kf in list(reversed(self._keyframes))[1:1 + RELOCALISE_TRIES]:
            if time.perf_counter() > deadline:
                break
            fit = self._bridge(view, kf, np.linalg.inv(self.poses[kf.index]) @ start, rounds=RELOCALISE_ROUNDS,
                               deadline=deadline)
            if self._confirmed(fit, view, kf):
                return self.poses[kf.index] @ fit.motion, 0.0
        self._why = (f"lost track: not placed by odometry ({why}; nor from the predicted pose, the last frame or "
                     f"{min(len(self._keyframes), 1 + RELOCALISE_TRIES)} recent keyframes)")
        return None

    _why = ""

    def _confirmed(self, fit: Fit, view: View, ref: View) -> bool:
        """A fit the depth accepted whose images agree too (`image_agreement` at least
        `TRACK_IMAGE_NCC`, or too little texture to judge)."""
        if not fit.ok:
            return False
        assert self._odometry is not None
        ncc = self._odometry.images_agree(view, ref, fit.motion)
        return ncc is None or ncc >= TRACK_IMAGE_NCC

    def _place_fitted(self, view: View, placed: tuple[np.ndarray, float]) -> None:
        """Place a fitted frame; it becomes the next keyframe when it lies `KEYFRAME_M` /
        `KEYFRAME_DEG` from the last one or confirmed less than `KEYFRAME_INLIERS` of it."""
        pose, share = placed
        gap_m, gap_deg = motion_gap(self.poses[self._keyframes[-1].index], pose)
        self._place(view, pose, keyframe=gap_m >= KEYFRAME_M or gap_deg >= KEYFRAME_DEG or share < KEYFRAME_INLIERS)

    def _fill_gap(self, view: View, deadline: float = float("inf")) -> Optional[tuple[np.ndarray, float]]:
        """A frame odometry could not place across a gap (no prediction yet, a fast move): the
        frame halfway between the last placed one and it is tracked first (as the offline estimate
        tries the frames in between), nearer still when that one fails, then the frame again;
        at most `GAP_FILLS` frames in between are read, each with the direct fits only, none
        after `deadline`. None when the gap stays unbridged (a source that no longer holds those
        frames: a camera's ring)."""
        assert self._last is not None
        target = view
        for _ in range(GAP_FILLS):
            mid = (self._last.index + target.index) // 2
            if mid <= self._last.index or time.perf_counter() > deadline:
                return None
            try:
                frame = self.source.frame(mid)
                if np.all(np.isfinite(frame.pose)):
                    return None
                self._names[mid], self.times[mid] = frame.name, frame.timestamp
                between = self._view(frame)
            except (FrameError, ValueError):
                return None
            placed = self._fit(between, deep=False)
            if placed is None:
                target = between
                continue
            self.tracked += 1
            self._place_fitted(between, placed)
            again = self._fit(view, deep=False)
            if again is not None:
                return again
            target = view
        return None

    def _bridge(self, view: View, target: View, guess: np.ndarray, min_share: Optional[float] = None,
                rounds: int = BRIDGE_ROUNDS, deadline: float = float("inf")) -> Fit:
        """The motion of `view` into `target` from a `guess`: up to `rounds` fits
        (`Odometry.fit_from`), each starting from the motion the last one reached, until one is
        accepted: overlap `RELOCALISE_OVERLAP` and agreement `RELOCALISE_AGREEMENT` (an older
        keyframe), or, with `min_share` (the last keyframe, as a direct fit is judged), that
        share of the view's depth confirmed; no round after the first starts past `deadline`."""
        assert self._odometry is not None
        fit = guessed = Fit(False, guess, 0.0, float("inf"))
        for k in range(rounds):
            if k and time.perf_counter() > deadline:
                break
            fit = self._odometry.fit_from(view, target, guessed.motion, RELOCALISE_OVERLAP, RELOCALISE_AGREEMENT)
            if min_share is not None and not fit.ok and fit.inliers >= min_share and np.all(np.isfinite(fit.motion)):
                fit = Fit(True, fit.motion, fit.inliers, fit.rms)
            if fit.ok or not np.all(np.isfinite(fit.motion)):
                break
            guessed = fit
        return fit

    def _hold(self, frame: Frame) -> None:
        self._held[frame.index] = frame
        for k in list(self._held):           # a copy: the mapping thread pops from it
            if k < frame.index - HELD_FRAMES:
                self._held.pop(k, None)

    # -- what tracking did -------------------------------------------------------------------------
    def summary(self) -> dict:
        """The `--json` summary's "tracking": frames tracked ("ran"), placed, lost ("lost track"),
        never tracked because mapping went past them ("skipped"), restarts, loop closures and the
        loop keyframes closed (`LoopCloser`), and the longest time
        without a pose between two placed frames (`longest_loss_s`, by the frames' timestamps)."""
        placed = sorted(self.poses)
        times = [self.times[i] for i in placed if i in self.times]
        gaps = np.diff(times) if len(times) > 1 else np.zeros(0)
        return {"ran": self.tracked, "placed": len(placed),
                "lost": sum(1 for r in self.lost.values() if r.startswith("lost track")),
                "skipped": max(0, self._next - len(self._names)), "restarts": self.restarts,
                "loop_closures": self._closer.loops if self._closer is not None else 0,
                "optimisations": self._closer.optimisations if self._closer is not None else 0,
                "loop_keyframes": len(self._closer.views) if self._closer is not None else 0,
                "longest_loss_s": round(float(gaps.max()), 3) if gaps.size else 0.0,
                "ms_mean": round(1000 * float(np.mean(self.seconds)), 1) if self.seconds else None,
                "ms_p95": round(1000 * float(np.percentile(self.seconds, 95)), 1) if self.seconds else None}

    def trajectory(self) -> tuple[list[float], np.ndarray]:
        """(timestamps, camera-to-world poses) of the placed frames, in frame order."""
        placed = [i for i in sorted(self.poses) if i in self.times]
        return [self.times[i] for i in placed], np.array([self.poses[i] for i in placed]).reshape(-1, 4, 4)

    def _place(self, view: View, pose: np.ndarray, keyframe: bool, restart: bool = False) -> None:
        self.poses[view.index] = pose
        self._history.append((self.times[view.index], pose))
        self._last = view
        self._lost_in_row = 0
        if keyframe:
            self._keyframes.append(view)
            self._offer_loop_keyframe(view, pose, restart)
        if self._loop_last is not None:
            self._anchor[view.index] = self._loop_last

    def _offer_loop_keyframe(self, view: View, pose: np.ndarray, restart: bool) -> None:
        """A keyframe `LOOP_KEYFRAME_M` / `LOOP_KEYFRAME_DEG` from the last loop keyframe (the
        offline estimate's spacing), or the first after a restart, goes to the loop closer with
        the chained motion from the last one (after a restart: "where tracking was", a robust
        edge loop closures may overrule)."""
        last = self._loop_last
        if last is not None and not restart:
            gap_m, gap_deg = motion_gap(self.poses[last], pose)
            if gap_m < LOOP_KEYFRAME_M and gap_deg < LOOP_KEYFRAME_DEG:
                return
        edge = None if last is None else (last, view.index, np.linalg.inv(self.poses[last]) @ pose, restart)
        self._loop_last = view.index
        if self._closer is not None:
            self._closer.offer(view.index, view.depth, view.gray, edge)

    # -- loop closure's corrections ----------------------------------------------------------------
    def _snapshot(self, indices: list[int]) -> dict[int, np.ndarray]:
        """The current poses of the loop keyframes `indices` (only `correct` changes them)."""
        return {i: self.poses[i].copy() for i in indices if i in self.poses}

    def correct(self, before: dict[int, np.ndarray], after: dict[int, np.ndarray]) -> None:
        """Move every placed frame with the loop keyframe it was placed after, from its pose in
        `before` to the optimised one in `after`: P <- after[a] before[a]^-1 P. Frames placed after
        the newest keyframe of `before` (tracking went on while the graph was optimised) move
        with that newest one, and so does the velocity history."""
        moves = {k: after[k] @ np.linalg.inv(before[k]) for k in before}
        newest = moves[max(moves)]
        with self._lock:
            for i, a in self._anchor.items():
                self.poses[i] = moves.get(a, newest) @ self.poses[i]
            self._history = deque(((t, newest @ P) for t, P in self._history), maxlen=self._history.maxlen)
            self.revision += 1

    def _lose(self, i: int, reason: str, counts: bool = True) -> None:
        self.lost[i] = reason
        if counts:
            self._lost_in_row += 1
