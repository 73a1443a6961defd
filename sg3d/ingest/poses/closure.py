"""The edges of a pose graph beyond odometry, shared by the offline pose estimate
(`sg3d.ingest.poses.estimate`) and online tracking's loop closer (`sg3d.ingest.poses.live_loops`):

- a new keyframe fitted straight to the few keyframes before it (`neighbour_edges`): one
  measurement over several odometry steps, so drift grows per keyframe, not per tracked frame;
- loop closures (`loop_edges`): a keyframe near an older one (by the current estimate) fitted to
  it, starting from the estimate.

A fit from a prediction is accepted when half of the depth overlaps the other view, 85 % of that
agrees within 3 cm (`Odometry.fit_from`), and it moves the estimate no more than the drift the
odometry can have (`consistent`).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from sg3d.ingest.poses.tracking import Fit, Odometry, View, motion_gap

LOOP_MIN_OVERLAP = 0.5       # a loop closure sees at least this share of the other keyframe's depth
LOOP_MIN_AGREEMENT = 0.85    # and this share of that agrees within 3 cm
LOOP_RADIUS_M, LOOP_AXIS_DEG = 0.6, 35.0
LOOP_SKIP_KEYFRAMES = 3      # the newest keyframes are neighbours, not loops
LOOP_CANDIDATES = 2
LOOP_MAX_GAP_M, LOOP_MAX_GAP_DEG = 0.3, 15.0
KEYFRAME_NEIGHBOURS = 2      # a new keyframe is fitted to this many previous ones

Edge = tuple[int, int, np.ndarray, bool]      # (from, to, motion of `to` into `from`, robust)


def consistent(predicted: np.ndarray, fit: Fit) -> bool:
    """An accepted fit whose motion lies within `LOOP_MAX_GAP_M` and `LOOP_MAX_GAP_DEG` of the
    predicted one (a larger jump is a wrong match, not drift)."""
    if not fit.ok:
        return False
    gap_m, gap_deg = motion_gap(predicted, fit.motion)
    return gap_m < LOOP_MAX_GAP_M and gap_deg < LOOP_MAX_GAP_DEG


def neighbour_edges(odometry: Odometry, view: View, poses: dict[int, np.ndarray], keyframes: Sequence[View]) -> list[Edge]:
    """Edges from the last `KEYFRAME_NEIGHBOURS` of `keyframes` (oldest first) to the new keyframe
    `view`, each fitted from the current estimate (`poses`)."""
    out = []
    pose = poses[view.index]
    for kf in list(keyframes)[-KEYFRAME_NEIGHBOURS:]:
        predicted = np.linalg.inv(poses[kf.index]) @ pose
        fit = odometry.fit_from(view, kf, predicted, LOOP_MIN_OVERLAP, LOOP_MIN_AGREEMENT)
        if consistent(predicted, fit):
            out.append((kf.index, view.index, fit.motion, True))
    return out


def loop_candidates(view: View, poses: dict[int, np.ndarray], keyframes: Sequence[View]) -> list[View]:
    """The older keyframes a new keyframe may close a loop with: all but the newest
    `LOOP_SKIP_KEYFRAMES`, within `LOOP_RADIUS_M` and with viewing axes within `LOOP_AXIS_DEG`
    (by the current estimate), the nearest `LOOP_CANDIDATES` of them."""
    pose = poses[view.index]
    old = list(keyframes)[:-LOOP_SKIP_KEYFRAMES] if len(keyframes) > LOOP_SKIP_KEYFRAMES else []
    near = []
    for kf in old:
        T = poses[kf.index]
        dist = float(np.linalg.norm(T[:3, 3] - pose[:3, 3]))
        axis = float(np.degrees(np.arccos(np.clip(T[:3, 2] @ pose[:3, 2], -1, 1))))
        if dist < LOOP_RADIUS_M and axis < LOOP_AXIS_DEG:
            near.append((dist, kf))
    return [kf for _, kf in sorted(near, key=lambda x: x[0])[:LOOP_CANDIDATES]]


def loop_edges(odometry: Odometry, view: View, poses: dict[int, np.ndarray], keyframes: Sequence[View]) -> list[Edge]:
    """Loop-closure edges of the new keyframe `view` to the `loop_candidates` among the earlier
    `keyframes` (oldest first), each fitted from the current estimate."""
    out = []
    pose = poses[view.index]
    for kf in loop_candidates(view, poses, keyframes):
        predicted = np.linalg.inv(poses[kf.index]) @ pose
        fit = odometry.fit_from(view, kf, predicted, LOOP_MIN_OVERLAP, LOOP_MIN_AGREEMENT)
        if consistent(predicted, fit):
            out.append((kf.index, view.index, fit.motion, True))
    return out
