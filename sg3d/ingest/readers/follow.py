"""A sequence folder that is still being written (`sg3d map FOLDER`): the frames complete so far.

Any folder layout sg3d reads can be followed. The folder is listed again whenever what it holds
changes (a cheap signature: entry counts of the folder and its sub-folders, sizes and times of
its text files: pose lists, intrinsics), and re-opened with the layout and depth registration
chosen the first time, so a frame's index never changes as long as frames are written in order.
A frame counts as complete once a later frame exists and the recording's image sizes rest on
SIZE_PROBES images, or once the folder has not changed for `settle_s` seconds (a writer that writes colour, depth and pose one after the other is never
caught half-way). Writers should still write each file under a temporary name and rename it:
a half-written image is otherwise skipped as corrupt, like in any recording.

A folder whose first complete frames carry no pose (no pose files, no trajectory: a bare RGB-D
camera's recorder) is followed without poses (`posed` False): its frames come with a NaN pose
and `sg3d.ingest.poses.online.OnlinePoses` tracks them, as `sg3d build` estimates them.
"""
from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Optional

from sg3d.ingest.readers.base import SIZE_PROBES, SIZE_WINDOW, Sequence, SequenceError, _parse_pose
from sg3d.ingest.readers.frames import Frame, FrameError
from sg3d.ingest.readers.pose_check import MotionRuns, causal_motion_problem

# A frame with no later frame is taken as complete after the folder was this long unchanged.
DEFAULT_SETTLE_S = 0.5
# Listing a folder costs more the more frames it holds (the kitchen's 1,000 frames: ~40 ms for the
# signature with pose files, ~90 ms to list them again on 2 busy cores), and every layout lists
# its own way: rather than list incrementally, the follower lists again at most so often that
# listing takes `LISTING_SHARE` of a core, and never waits more than `MAX_LISTING_WAIT_S`.
LISTING_SHARE = 0.2
MAX_LISTING_WAIT_S = 0.5
# Runs of poses kept while following (`pose_check.MotionRuns`): a recording with more separate
# jumps than this lets its oldest runs go (the path so far is always kept).
MOTION_RUNS_HELD = 32


def listing_interval(cost_s: float) -> float:
    """Seconds until the folder is listed again after a listing (signature and, when it changed,
    re-opening) that took `cost_s`: cost / `LISTING_SHARE` (listing takes at most that share of a
    core), at most `MAX_LISTING_WAIT_S`."""
    return min(MAX_LISTING_WAIT_S, cost_s / LISTING_SHARE)


def folder_signature(path: Path) -> tuple:
    """What changes when a frame is added: entry counts of the folder and of its sub-folders,
    and the size and time of its top-level files other than images (pose lists, intrinsics)."""
    sig: list = []
    try:
        with os.scandir(path) as it:
            entries = list(it)
    except OSError:
        return ()
    sig.append(len(entries))
    for e in sorted(entries, key=lambda e: e.name):
        try:
            if e.is_dir(follow_symlinks=False):
                sig.append((e.name, sum(1 for _ in os.scandir(e.path))))
            elif not e.name.lower().endswith((".png", ".jpg", ".jpeg")):
                st = e.stat()
                sig.append((e.name, st.st_size, st.st_mtime_ns))
        except OSError:
            continue
    return tuple(sig)


class FolderFollower:
    """Follows `path` as frames are written into it; `poll()` says how many frames are complete,
    `seq` is the sequence as last listed (its frame i is frame i of every later listing)."""

    def __init__(self, path: Path, layout: Optional[str] = None, settle_s: float = DEFAULT_SETTLE_S):
        self.path = Path(path).expanduser()
        self.layout = layout
        self.settle_s = float(settle_s)
        self.seq: Optional[Sequence] = None
        self.waiting_for = "the first frames"      # why nothing could be opened yet
        self._signature: tuple = ()
        self._changed_at = time.monotonic()
        self._motion: dict[int, str] = {}     # frame -> why its pose is no plausible move
        self._runs = MotionRuns(max_runs=MOTION_RUNS_HELD)
        self._judged = 0                       # frames before this one had their motion judged
        self._ended = False                    # `whole()` was called
        self.posed: Optional[bool] = None      # whether the frames carry poses (decided on the first ones)
        self._next_listing = 0.0               # monotonic time before which the folder is not listed again
        self._listed_at = 0.0                  # monotonic time of the last listing

    def poll(self) -> int:
        """The number of complete frames (0 while the folder holds no readable sequence yet)."""
        if not self.path.is_dir():
            raise SequenceError(f"sequence folder not found: {self.path}")
        now = time.monotonic()
        if now >= self._next_listing:
            t0 = time.perf_counter()
            sig = folder_signature(self.path)
            if sig != self._signature:
                self._signature, self._changed_at = sig, now
                self._reopen()
            self._next_listing = now + listing_interval(time.perf_counter() - t0)
            self._listed_at = now
        if self.seq is None:
            return 0
        n = len(self.seq)
        if self._listed_at - self._changed_at >= self.settle_s:     # seen unchanged by a listing that long after
            ready = n
        else:
            ready = max(0, n - 1) if self._sizes_known(self.seq) else 0
        if ready and self.posed is None:
            self.posed = self.seq.has_poses()
        return ready

    def _reopen(self) -> None:
        from sg3d.ingest.readers import open_sequence

        old = self.seq
        try:
            if old is None:
                seq = open_sequence(self.path, self.layout)
            else:
                seq = open_sequence(self.path, old.layout, registration=old.registration)
        except SequenceError as exc:
            if old is None:
                self.waiting_for = str(exc)
                return
            raise
        if old is not None:
            for name, reason in old.skipped:
                seq.skip(name, reason)
            if len(seq) < len(old):
                raise SequenceError(f"frames disappeared from {self.path} while it was followed "
                                    f"({len(old)} before, {len(seq)} now)")
        # the whole-recording motion check (`Sequence.motion_problems`) would re-read every pose at
        # each listing and judge the newest frame without its next neighbour: while following, each
        # frame is judged once, in order, against the frames before it (`_judge_motion_to`)
        seq._motion = None if self._ended else self._motion
        _ = seq.depth_size   # probed now, over the frames of this listing
        self.seq = seq

    def _sizes_known(self, seq: Sequence) -> bool:
        """Whether the colour and depth sizes rest on SIZE_PROBES images each: with fewer (the
        first frames of a recording) one odd image could still set them; past SIZE_WINDOW frames
        the probes have seen all they ever look at."""
        return len(seq) > SIZE_WINDOW or (seq.size_votes >= SIZE_PROBES
                                          and getattr(seq, "depth_votes", 0) >= SIZE_PROBES)

    def _judge_motion_to(self, i: int) -> None:
        """Judge the poses of every frame up to i not judged yet, in order, as they arrived
        (`pose_check.causal_motion_problem`); a frame's verdict never changes afterwards."""
        assert self.seq is not None
        seq = self.seq
        while self._judged <= i:
            k = self._judged
            self._judged += 1
            try:
                pose = _parse_pose(seq._entries[k])
            except FrameError:
                continue                       # named when the frame is reached
            why = causal_motion_problem(self._runs, k, pose, seq.timestamp_of(k), seq.name_of(k), seq.name_of)
            if why:
                self._motion[k] = why

    def whole(self) -> Optional[Sequence]:
        """The recording as a build reads it, once it ended: the motion check over the whole
        recording (`Sequence.motion_problems`) instead of the one frame by frame."""
        self._ended = True
        if self.seq is not None:
            self.seq._motion = None
        return self.seq

    def frame(self, i: int) -> Frame:
        """Frame i, lazily decoded (FrameError when it is bad; recorded in `seq.skipped`)."""
        assert self.seq is not None
        if self.posed is False:
            return self.seq.unposed_frame(i)
        if self.seq._motion is self._motion:
            self._judge_motion_to(i)
        return self.seq.frame(i, lazy=True)

    def written_at(self, i: int) -> float:
        """When frame i was written (its colour file's time; wall clock, as `time.time()`)."""
        assert self.seq is not None
        try:
            return self.seq._entries[i].color.stat().st_mtime
        except OSError:
            return time.time()
