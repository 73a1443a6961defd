"""Poses for a live source that has none (a RealSense camera, an MCAP recording without /tf or
odometry): RGB-D odometry as the frames arrive (`sg3d map realsense`).

`OnlinePoses` wraps a `sg3d.ingest.live.LiveSource` whose frames carry no pose (a NaN matrix)
and gives each frame, the first time it is read, a camera-to-world pose (world = the first
tracked camera; the live mapper estimates up and floor from the frames themselves):

- the frame is fitted to the last keyframe (`Odometry.fit`, trust check: `TRACK_MIN_INLIERS`
  of its depth confirmed), and its pose is the keyframe's pose chained with that motion;
  it becomes the next keyframe when it lies `KEYFRAME_M` / `KEYFRAME_DEG` away from the last one
  or shows less than `KEYFRAME_INLIERS` in common with it (drift grows per keyframe, not per
  frame);
- when that fit fails, the frame is fitted to the last placed frame, then re-localised against
  the `RELOCALISE_KEYFRAMES` most recent keyframes, starting from the last known pose
  (`Odometry.fit_from`);
- a frame none of them places is skipped with the reason "lost track: ..." (`FrameError`, so
  the mapper lists it and goes on); the next placeable frame continues from the last known pose.
  After `MAX_LOST` unplaceable frames in a row (that still show enough depth) the track restarts:
  the next such frame becomes a keyframe at the last known pose (counted in `restarts`).

A frame that already carries a finite pose passes through untouched. Odometry runs at about 320
px width (`sg3d.ingest.poses.tracking`): 15-40 ms a frame on 2 cores. Memory: a pose per frame
(128 bytes) and the reduced views of the recent keyframes.
"""
from __future__ import annotations

import threading
from collections import deque
from typing import Optional

import numpy as np

from sg3d.ingest.poses.tracking import Odometry, View, motion_gap
from sg3d.ingest.readers.frames import Frame, FrameError

TRACK_MIN_INLIERS = 0.5      # share of a frame's depth the keyframe must confirm (as `estimate`)
KEYFRAME_M, KEYFRAME_DEG = 0.05, 5.0   # measured on the kitchen: 0.05 m / 5 deg ATE 6 mm, 0.1 m / 10 deg 37 mm
KEYFRAME_INLIERS = 0.7       # a frame sharing less than this with the keyframe becomes the next one
RELOCALISE_KEYFRAMES = 5     # recent keyframes a lost frame is tried against
RELOCALISE_OVERLAP, RELOCALISE_AGREEMENT = 0.4, 0.8
MAX_LOST = 3                 # unplaceable frames in a row before the track restarts at the last pose


class OnlinePoses:
    """A `LiveSource` that gives the frames of a pose-less one a pose by odometry (module doc)."""

    def __init__(self, source, max_depth: float = 4.0):
        self.source = source
        self.max_depth = max_depth
        self.seq = None                               # no sequence to read again: the final graph is live
        self.poses: dict[int, np.ndarray] = {}
        self.lost: dict[int, str] = {}                # frame -> reason (the source's own FrameErrors too)
        self.tracked = 0
        self.restarts = 0
        self._names: dict[int, str] = {}
        self._next = 0                                # next frame to track
        self._odometry: Optional[Odometry] = None
        self._keyframes: deque[View] = deque(maxlen=RELOCALISE_KEYFRAMES)
        self._last: Optional[View] = None             # the last placed frame
        self._lost_in_row = 0
        self._lock = threading.Lock()

    # -- the LiveSource protocol ------------------------------------------------------------------
    @property
    def waiting_for(self) -> str:
        return getattr(self.source, "waiting_for", "the first frames")

    def poll(self) -> int:
        return self.source.poll()

    def written_at(self, i: int) -> float:
        return self.source.written_at(i)

    def frame(self, i: int) -> Frame:
        """Frame i with its pose, tracked from the last placed frame when i is new (frames the mapper
        jumped over while behind are not tracked); FrameError "lost track: ..." when odometry could
        not place it."""
        with self._lock:
            if i >= self._next:          # frames the mapper jumped over are never tracked
                self._track(i)
                self._next = i + 1
        if i in self.lost:
            raise FrameError(self._names.get(i, f"frame {i}"), self.lost[i])
        frame = self.source.frame(i)
        if i not in self.poses:
            raise FrameError(frame.name, "not tracked: mapping went past it (it was behind the camera)")
        frame.pose = self.poses[i]
        return frame

    # -- tracking ---------------------------------------------------------------------------------
    def _track(self, i: int) -> None:
        try:
            frame = self.source.frame(i)
            self._names[i] = frame.name
            if np.all(np.isfinite(frame.pose)):
                self.poses[i] = frame.pose
                return
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
            pose, share = placed
            key = self._keyframes[-1]
            gap_m, gap_deg = motion_gap(self.poses[key.index], pose)
            self._place(view, pose, keyframe=gap_m >= KEYFRAME_M or gap_deg >= KEYFRAME_DEG or share < KEYFRAME_INLIERS)
            return
        if self._lost_in_row >= MAX_LOST:              # a new track from the last known pose
            self.restarts += 1
            self._keyframes.clear()
            self._place(view, self.poses[self._last.index], keyframe=True)
            return
        self._lose(i, self._why)

    def _view(self, frame: Frame) -> View:
        if self._odometry is None:
            self._odometry = Odometry(frame.K, frame.size, self.max_depth)
        return self._odometry.view(frame.index, frame.depth, frame.gray)

    def _fit(self, view: View) -> Optional[tuple[np.ndarray, float]]:
        """(pose, share of its depth confirmed) from the last keyframe, the last placed frame, or
        the recent keyframes starting from the last known pose; None (reason in `_why`)."""
        assert self._odometry is not None and self._last is not None
        odo = self._odometry
        key = self._keyframes[-1]
        fit = odo.fit(view, key, TRACK_MIN_INLIERS)
        if fit.ok:
            return self.poses[key.index] @ fit.motion, fit.inliers
        why = f"against keyframe {key.index}: {fit.why}"
        if self._last.index != key.index:
            fit = odo.fit(view, self._last, TRACK_MIN_INLIERS)
            if fit.ok:
                return self.poses[self._last.index] @ fit.motion, 0.0   # a keyframe from here on
        last_pose = self.poses[self._last.index]
        for kf in reversed(self._keyframes):
            predicted = np.linalg.inv(self.poses[kf.index]) @ last_pose
            fit = odo.fit_from(view, kf, predicted, RELOCALISE_OVERLAP, RELOCALISE_AGREEMENT)
            if fit.ok:
                return self.poses[kf.index] @ fit.motion, 0.0
        self._why = f"lost track: not placed by odometry ({why}; nor against the last frame or {len(self._keyframes)} recent keyframes)"
        return None

    _why = ""

    def _place(self, view: View, pose: np.ndarray, keyframe: bool) -> None:
        self.poses[view.index] = pose
        self._last = view
        self._lost_in_row = 0
        if keyframe:
            self._keyframes.append(view)

    def _lose(self, i: int, reason: str, counts: bool = True) -> None:
        self.lost[i] = reason
        if counts:
            self._lost_in_row += 1
