"""Which frames the detector runs on: KGE's keyframes and anchors, and one sharp frame from
every stretch of the recording that KGE left without one, up to a frame budget.

KGE (Algorithm 1) keeps a frame only when the view has moved far from the current keyframe and
anchor, which leaves 2-5 % of a hand-held sequence: an object that the detector finds in one
view in ten is then seen once or never. Detection is the expensive step, so extra frames are
added, and they are chosen LOCALLY: the sharp frames, in recording order, are cut into
budget-many consecutive windows, and a window that holds no KGE frame contributes its sharpest
frame (ABIR's variance of Laplacian, an image-only score).

Why local: KGE's decisions are sequential thresholds on poses, so a pose that moves by a tenth
of a degree moves an anchor by a frame or two. A global choice that starts from the KGE frames
(farthest-point sampling in viewpoint space) then shifts every later pick, and the graph
becomes a property of the pose noise rather than of the recording. Here the windows come from
the blur decisions alone, so a KGE frame that moves changes the picks of the windows it leaves
and enters, nothing else; a recording whose poses are estimated detects nearly the same frames
as one whose poses are given.

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


@dataclass(frozen=True)
class Candidate:
    """A sharp frame: its index and its sharpness (ABIR's variance of Laplacian V_t, Eq. 1)."""

    index: int
    sharpness: float


def frame_budget(n_sharp: int, fraction: float = DEFAULT_FRACTION, min_frames: int = MIN_FRAMES) -> int:
    """How many frames to detect: max(min_frames, fraction * n_sharp), never more than exist."""
    return int(min(n_sharp, max(min_frames, round(fraction * n_sharp))))


def window_edges(n: int, windows: int) -> np.ndarray:
    """Cut n frames in order into `windows` consecutive windows of nearly equal count: window k
    holds positions [round(k n / W), round((k + 1) n / W)), k = 0 .. W - 1 (W = min(windows, n))."""
    count = max(1, min(int(windows), n))
    return np.rint(np.linspace(0, n, count + 1)).astype(int)


def choose_frames(candidates: Sequence[Candidate], required: Sequence[int], budget: int) -> list[int]:
    """Frame indices to detect, in sequence order: every `required` frame (KGE keyframes and
    anchors) that is a candidate, plus, for each of the `budget` windows of `window_edges` over
    the candidates in order that holds no required frame, its sharpest frame (ties go to the
    earlier frame, so the choice is deterministic).

    A frame that joins or leaves `required` changes the picks of its own window only; the
    result has at most budget + len(required) frames, and about max(budget, len(required))
    where KGE's frames are spread along the recording."""
    ordered = sorted(candidates, key=lambda c: c.index)
    if not ordered:
        return []
    index = np.array([c.index for c in ordered])
    sharpness = np.array([c.sharpness for c in ordered], dtype=np.float64)
    is_required = np.isin(index, np.fromiter(set(required), dtype=np.int64, count=len(set(required))))
    chosen = index[is_required].tolist()
    edges = window_edges(len(ordered), budget)
    for a, b in zip(edges[:-1], edges[1:]):
        if b > a and not is_required[a:b].any():
            chosen.append(int(index[a + int(np.argmax(sharpness[a:b]))]))  # argmax: the first maximum
    return sorted(chosen)
