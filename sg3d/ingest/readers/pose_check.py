"""The check every camera pose passes before its frame is used, whatever layout it came from."""
from __future__ import annotations

from typing import Any, Callable, Optional, Sequence

import numpy as np

from sg3d.core.model import WORLD_EXTENT_M

ROTATION_TOLERANCE = 1e-3    # |R^T R - I| entries of a rigid rotation
BOTTOM_ROW_TOLERANCE = 1e-6  # |last row - (0, 0, 0, 1)|


def pose_problem(pose: np.ndarray, source: str = "the pose") -> Optional[str]:
    """Why a 4x4 camera-to-world `pose` cannot be used, or None. Rule: every entry finite; the
    rotation block orthonormal with determinant +1 (rigid, no reflection); the bottom row
    (0, 0, 0, 1); the translation within +-WORLD_EXTENT_M metres."""
    pose = np.asarray(pose, dtype=np.float64)
    if pose.shape != (4, 4):
        return f"{source} is not a 4x4 matrix"
    if not np.all(np.isfinite(pose)):
        return f"{source} is not finite (tracking lost)"
    t = pose[:3, 3]
    if np.abs(t).max() > WORLD_EXTENT_M:
        return f"{source} places the camera {np.abs(t).max():.3g} m away, beyond {WORLD_EXTENT_M:g} m"
    R = pose[:3, :3]
    if (np.abs(R.T @ R - np.eye(3)).max() > ROTATION_TOLERANCE
            or np.abs(pose[3] - (0, 0, 0, 1)).max() > BOTTOM_ROW_TOLERANCE):
        return f"{source} is not a rigid transform"
    if np.linalg.det(R) < 0:   # orthonormal but mirrored: no camera moves like that
        return f"{source} is a reflection (determinant -1), not a rotation"
    return None


def rigid(pose: np.ndarray) -> np.ndarray:
    """A pose that passed `pose_problem` with its rotation block replaced by the nearest rotation
    (scipy's `Rotation.from_matrix`). Rule "one camera, one pose": a layout that stores 4x4
    matrices rounded to a few digits (7-Scenes) and one that stores quaternions (a bag) then give
    the same camera, to the last bits, instead of poses a millimetre apart."""
    out = np.array(pose, dtype=np.float64, copy=True)
    from scipy.spatial.transform import Rotation   # here: importing it costs every `sg3d` start ~0.2 s

    out[:3, :3] = Rotation.from_matrix(out[:3, :3]).as_matrix()
    out[3] = (0.0, 0.0, 0.0, 1.0)
    return out


# -- continuity: how far a camera can move between two frames --------------------------------------
# A person walking with a camera moves at ~1.5 m/s, an indoor robot at 0.5-2 m/s; the three sample
# recordings peak at 1.3 m/s (kitchen 1.09, living room 1.30, study room 0.57 m/s between frames).
# 10 m/s is a sprint: no camera a room is scanned with gets there, so a faster step is a pose
# error (a glitch, a block of frames shifted or from another recording), not motion.
MAX_SPEED_M_S = 10.0
# A person turns the head at up to ~400-700 deg/s in a quick glance; a hand-held or robot camera
# turns much slower (the samples peak at 48 deg/s). Two full turns a second is no camera's motion.
MAX_TURN_RATE_DEG_S = 720.0
# Allowed on top of the rates in any one step: tracking jitter and rounded pose files (a few cm and
# a degree on the samples), and clocks that tick unevenly.
STEP_SLACK_M = 0.1
STEP_SLACK_DEG = 5.0
# Two frames are never taken as closer in time than this (equal or out-of-order timestamps, a
# layout that numbers frames without a clock): 60 Hz, the fastest depth cameras sg3d reads.
MIN_STEP_S = 1.0 / 60.0


def motion_problem(a: np.ndarray, b: np.ndarray, dt: float) -> Optional[str]:
    """Why a camera cannot have moved from pose `a` to pose `b` (4x4 camera-to-world) in `dt`
    seconds, or None. Rule: the distance between the camera centres is at most
    MAX_SPEED_M_S * dt + STEP_SLACK_M and the angle of the relative rotation at most
    MAX_TURN_RATE_DEG_S * dt + STEP_SLACK_DEG (dt at least MIN_STEP_S)."""
    dt = max(abs(float(dt)), MIN_STEP_S)
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    dist = float(np.linalg.norm(b[:3, 3] - a[:3, 3]))
    if dist > MAX_SPEED_M_S * dt + STEP_SLACK_M:
        return (f"the camera jumps {dist:.3g} m in {dt:.3g} s ({dist / dt:.3g} m/s; a hand-held or robot "
                f"camera moves at most {MAX_SPEED_M_S:g} m/s)")
    cos = (np.trace(a[:3, :3].T @ b[:3, :3]) - 1.0) / 2.0
    angle = float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    if angle > MAX_TURN_RATE_DEG_S * dt + STEP_SLACK_DEG:
        return (f"the camera turns {angle:.3g} deg in {dt:.3g} s ({angle / dt:.3g} deg/s; a hand-held or robot "
                f"camera turns at most {MAX_TURN_RATE_DEG_S:g} deg/s)")
    return None


class MotionRuns:
    """The runs of poses that can belong to one camera's path, grown one frame at a time in order
    (the rule of `implausible_motion`): a frame joins the run of the frame before it when the step
    is plausible (`motion_problem`), else the most recent earlier run it can be reached from (a
    shifted block ends where the path comes back), else it opens a new run. `add` returns the run
    the frame joined; `path` is the run with the most frames so far (ties: the earliest)."""

    def __init__(self, max_runs: Optional[int] = None):
        self.runs: list[dict[str, Any]] = []     # {last: index, pose, stamp, count, why: str}
        self.current: Optional[dict[str, Any]] = None
        self.max_runs = max_runs       # live: the oldest runs besides the path are let go past this

    def add(self, i: int, pose: np.ndarray, stamp: float, name: str,
            names: Callable[[int], str]) -> dict[str, Any]:
        """Frame i (its camera-to-world `pose`, time `stamp`) joins a run; `names(k)` is frame k's name."""
        current = self.current
        home: Optional[dict[str, Any]] = current
        if current is None:
            home = {"last": i, "pose": pose, "stamp": stamp, "count": 0, "why": ""}
            self.runs.append(home)
        else:
            why = motion_problem(current["pose"], pose, stamp - current["stamp"])
            if why is not None:
                home = next((r for r in sorted(self.runs, key=lambda r: -r["last"]) if r is not current and
                             motion_problem(r["pose"], pose, stamp - r["stamp"]) is None), None)
                if home is None:
                    home = {"last": i, "pose": pose, "stamp": stamp, "count": 0,
                            "why": f"{why} from {names(current['last'])}"}
                    self.runs.append(home)
                    if not current["why"]:          # the first run: named by the jump that ended it
                        current["why"] = f"{why} to {name}"
        assert home is not None
        home["count"] += 1
        home["last"], home["pose"], home["stamp"] = i, pose, stamp
        self.current = home
        if self.max_runs is not None and len(self.runs) > self.max_runs:
            path = self.path
            self.runs.remove(min((r for r in self.runs if r is not path and r is not home), key=lambda r: r["last"]))
        return home

    @property
    def path(self) -> Optional[dict[str, Any]]:
        return max(self.runs, key=lambda r: r["count"]) if self.runs else None   # max keeps the first of equals


def implausible_motion(poses: Sequence[Optional[np.ndarray]], stamps: Sequence[float],
                       names: Sequence[str]) -> dict[int, str]:
    """Frame index -> why its pose is left out, for the frames whose poses cannot belong to one
    camera's path with the rest (`motion_problem`), over the whole recording: the frames are put
    into runs in order (`MotionRuns`); the run with the most frames is the camera's path (ties:
    the earliest); every other run's frames are named, with the jump that opened their run. A
    pose of None (missing, unusable) is passed over."""
    runs = MotionRuns()
    member: dict[int, int] = {}
    for i, pose in enumerate(poses):
        if pose is not None:
            member[i] = id(runs.add(i, pose, stamps[i], names[i], names.__getitem__))
    if len(runs.runs) < 2:
        return {}
    path = runs.path
    whys = {id(r): r["why"] for r in runs.runs}
    return {i: whys[r] for i, r in member.items() if r != id(path)}


def causal_motion_problem(runs: MotionRuns, i: int, pose: np.ndarray, stamp: float, name: str,
                          names: Callable[[int], str]) -> Optional[str]:
    """Why frame i's pose is left out when it is judged as it arrives (a live map), or None. Rule:
    the frame joins a run of `runs` (`MotionRuns.add`); it is kept when that run is the path so
    far (the most frames), else named with the jump that opened its run. The same verdicts as
    `implausible_motion` for any damage the path outnumbers when it happens (a glitch, a shifted
    block); a block at the very start that the later path outgrows is named by the whole-recording
    check but was kept when it arrived, and the first frames after it are named until it is."""
    home = runs.add(i, pose, stamp, name, names)
    return None if home is runs.path else home["why"] or "no plausible move from the frames before it"
