"""Which frames the detector runs on: KGE's keyframes and anchors, then the sharp frames that add
the most new viewpoints, up to a frame budget; each choice then stands for its stretch of the
recording, and the stretch's sharpest frame is the one detected.

KGE (Algorithm 1) keeps a frame only when the view has moved far from the current keyframe and
anchor, which leaves 2-5 % of a hand-held sequence: an object that the detector finds in one
view in ten is then seen once or never. Detection is the expensive step, so the extra frames are
chosen for what they add: farthest-point sampling in a viewpoint space (camera position and
viewing direction), starting from the KGE frames.

Both choices are thresholds and maxima over poses, so a pose that moves by a tenth of a degree
moves a KGE anchor or a farthest-point pick to a frame one to four frames away, and the
detector, which finds an object in one view and misses it in the next, then makes a different
graph. So the choices only say WHERE to detect: the sharp frames, in recording order, are cut
into fixed windows of `SNAP_WINDOW` frames (from the blur decisions alone), and a window that
received k choices detects its k sharpest frames (ABIR's variance of Laplacian, an image-only
score). A choice that moves within its window changes nothing; one that crosses into the next
window changes that window's frames only.

The choice depends only on the poses, the blur decisions and the settings, never on timing, so
a build and its `--resume` detect the same frames.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

# Budget: the share of the sharp frames that is detected (the default keeps a 1000-frame
# sequence at >= 60 input frames/s on 2 cores at ~60 ms per detection), and a floor so a short
# walk through a room still sees every object from several views.
DEFAULT_FRACTION = 0.15
MIN_FRAMES = 40
# Viewpoint space scales: moving this far, or turning the optical axis by this chord length
# (0.25 ~ 14 degrees), counts as one unit of new view.
POSITION_SCALE_M = 0.30
DIRECTION_SCALE = 0.25
# Sharp frames per window: a choice moved by pose noise (1-4 frames, measured on the kitchen)
# mostly stays in its window, and a window is short enough (1/6 s of a 30 Hz recording) that its
# sharpest frame still shows the view that was chosen. Measured on the kitchen through the whole
# build: 5 kept the farthest-point picks' quality; 7 and 10 were steadier but lost precision.
SNAP_WINDOW = 5


@dataclass(frozen=True)
class Candidate:
    """A sharp frame: its index, camera-to-world pose and sharpness (ABIR's variance of
    Laplacian V_t, Eq. 1)."""

    index: int
    pose: np.ndarray
    sharpness: float


def viewpoint_features(poses: Sequence[np.ndarray]) -> np.ndarray:
    """Each pose as (position / POSITION_SCALE_M, optical axis / DIRECTION_SCALE): Euclidean
    distance in this space is the viewpoint distance d = sqrt(|dt|^2 / s_t^2 + |dz|^2 / s_r^2)."""
    if not len(poses):
        return np.zeros((0, 6))
    P = np.asarray(poses, dtype=np.float64)
    return np.hstack([P[:, :3, 3] / POSITION_SCALE_M, P[:, :3, 2] / DIRECTION_SCALE])


def frame_budget(n_sharp: int, fraction: float = DEFAULT_FRACTION, min_frames: int = MIN_FRAMES) -> int:
    """How many frames to detect: max(min_frames, fraction * n_sharp), never more than exist."""
    return int(min(n_sharp, max(min_frames, round(fraction * n_sharp))))


def recording_budget(sharp_judged: int, judged: int, received: int, fraction: float = DEFAULT_FRACTION,
                     min_frames: int = MIN_FRAMES) -> int:
    """Rule "a live source's detection budget is a build's": `frame_budget` of the recording's
    sharp frames, estimated as the frames `received` times the sharp share of those `judged` (a
    source tracked live judges only the frames tracking took: a budget of the judged ones
    shrank with the CPU tracking had), never more than the `sharp_judged` frames there are to
    choose from."""
    if judged <= 0 or sharp_judged <= 0:
        return 0
    sharp = round(sharp_judged * max(received, judged) / judged)
    return min(sharp_judged, frame_budget(int(sharp), fraction, min_frames))


def farthest_viewpoints(candidates: Sequence[Candidate], required: Sequence[int], budget: int) -> list[int]:
    """Every `required` frame (KGE keyframes and anchors) that is a candidate, then greedy
    farthest-point sampling over `candidates` in viewpoint space until `budget` frames are chosen
    (ties go to the earlier frame, so the choice is deterministic); in sequence order."""
    if not candidates:
        return []
    index = np.array([c.index for c in candidates])
    feats = viewpoint_features([c.pose for c in candidates])
    known = set(index.tolist())
    chosen = [i for i in sorted(set(required)) if i in known]
    position = {int(i): k for k, i in enumerate(index)}
    dist = np.full(len(candidates), np.inf)
    for i in chosen:
        dist = np.minimum(dist, np.linalg.norm(feats - feats[position[i]], axis=1))
    picked = set(chosen)
    if not chosen:  # nothing required: start from the first frame
        first = int(index[0])
        chosen.append(first)
        picked.add(first)
        dist = np.linalg.norm(feats - feats[0], axis=1)
    while len(chosen) < min(budget, len(candidates)):
        k = int(np.argmax(dist))  # argmax returns the first maximum: the earliest frame
        i = int(index[k])
        if i in picked or dist[k] <= 0:  # every remaining frame repeats a chosen view exactly
            break
        chosen.append(i)
        picked.add(i)
        dist = np.minimum(dist, np.linalg.norm(feats - feats[k], axis=1))
    return sorted(chosen)


def window_edges(n: int, window: int) -> np.ndarray:
    """Cut n frames in order into W = max(1, round(n / window)) consecutive windows of nearly
    equal count: window k holds positions [round(k n / W), round((k + 1) n / W))."""
    count = max(1, min(n, int(round(n / max(1, window)))))
    return np.rint(np.linspace(0, n, count + 1)).astype(int)


def sharpest_in_windows(candidates: Sequence[Candidate], choices: Sequence[int], window: int = SNAP_WINDOW) -> list[int]:
    """Each window of `window_edges` over the candidates (in sequence order) that holds k of the
    `choices` detects its k sharpest frames instead (ties go to the earlier frame); in
    sequence order. The number of frames is kept; only frames inside a choice's window move."""
    ordered = sorted(candidates, key=lambda c: c.index)
    if not ordered:
        return []
    index = np.array([c.index for c in ordered])
    sharpness = np.array([c.sharpness for c in ordered], dtype=np.float64)
    edges = window_edges(len(ordered), window)
    known = set(index.tolist())
    slot = np.searchsorted(index, sorted(i for i in set(choices) if i in known))
    per_window = np.bincount(np.searchsorted(edges, slot, side="right") - 1, minlength=len(edges) - 1)
    out: list[int] = []
    for w in np.flatnonzero(per_window):
        a, b = edges[w], edges[w + 1]
        best = np.argsort(-sharpness[a:b], kind="stable")[:per_window[w]]
        out.extend(int(index[a + k]) for k in best)
    return sorted(out)


def choose_frames(candidates: Sequence[Candidate], required: Sequence[int], budget: int) -> list[int]:
    """Frame indices to detect, in sequence order: the KGE frames and the farthest new
    viewpoints (`farthest_viewpoints`, at least `budget` frames), each moved to the sharpest
    frame of its window (`sharpest_in_windows`)."""
    budget = max(budget, len(set(required)))
    return sharpest_in_windows(candidates, farthest_viewpoints(candidates, required, budget))
