"""Keyframe group extraction (KGE, paper Sec. IV-B, Algorithm 1, Eq. 5-6).

Frames are sorted into keyframes (a group's reference), anchors (frames that moved far enough
from the previous anchor to show something new) and garbage (redundant, dropped). Overlap
between two frames is measured by sampling pixels with valid depth in the source frame,
back-projecting them, moving them by the relative pose and projecting them into the target
(Eq. 6); the overlap is the fraction that lands inside the target image in front of its
camera (Eq. 5, estimated on `n_points` samples instead of every pixel: the paper's O(WH)
becomes O(n), ~0.1 ms).

Only the current keyframe, the active anchor and the frames of the open group are kept; the
back-projected samples of the keyframe and the anchor are computed once and reused for every
incoming frame, and incoming frames need nothing but their pose until they become a keyframe
or an anchor (so garbage frames are never decoded beyond what blur rejection needed).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable, Iterator, Optional

import numpy as np

from sg3d.ingest.readers.frames import Frame

DEFAULT_T_KEY = 0.2
DEFAULT_T_ANCHOR = 0.68
DEFAULT_POINTS = 1000


def sample_depth_pixels(depth: np.ndarray, n_points: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Up to n_points pixels (u, v, depth) drawn uniformly among those with valid depth."""
    valid = np.flatnonzero(depth.ravel() > 0)
    if valid.size == 0:
        empty = np.zeros(0)
        return empty, empty, empty
    pick = valid if valid.size <= n_points else rng.choice(valid, size=n_points, replace=False)
    w = depth.shape[1]
    v, u = np.divmod(pick, w)
    return u.astype(np.float64), v.astype(np.float64), depth.ravel()[pick].astype(np.float64)


def backproject(u: np.ndarray, v: np.ndarray, d: np.ndarray, K: np.ndarray) -> np.ndarray:
    """D(p) K^-1 p for pixels p = (u, v, 1): Nx3 points in the camera frame."""
    x = (u - K[0, 2]) / K[0, 0] * d
    y = (v - K[1, 2]) / K[1, 1] * d
    return np.stack([x, y, d], axis=1)


def relative_pose(src_pose: np.ndarray, dst_pose: np.ndarray) -> np.ndarray:
    """T_{i,j}: source camera coordinates -> target camera coordinates (poses camera-to-world)."""
    return np.linalg.solve(dst_pose, src_pose)


def reproject(points_src: np.ndarray, T_rel: np.ndarray, K_dst: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. 6: p' = K T_{i,j} D(p) K^-1 p, given the back-projected D(p) K^-1 p (Nx3).

    Returns the target pixel coordinates (u', v') and the depth z' in the target camera."""
    q = points_src @ T_rel[:3, :3].T + T_rel[:3, 3]
    z = q[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = K_dst[0, 0] * q[:, 0] / z + K_dst[0, 2]
        v = K_dst[1, 1] * q[:, 1] / z + K_dst[1, 2]
    return u, v, z


def overlap_fraction(u: np.ndarray, v: np.ndarray, z: np.ndarray, width: int, height: int) -> float:
    """Eq. 5: the share of projected points p' that land in I_{W,H} (and in front of the camera).

    Pixel (x, y) covers [x - 0.5, x + 0.5); a point counts when it rounds into the image."""
    if u.size == 0:
        return 0.0
    inside = (z > 0) & (u >= -0.5) & (u < width - 0.5) & (v >= -0.5) & (v < height - 0.5)
    return float(np.count_nonzero(inside)) / u.size


@dataclass
class SampledFrame:
    """A frame's back-projected depth samples, reused while it is keyframe or anchor."""

    frame: Frame
    points: np.ndarray  # Nx3, source camera frame

    @classmethod
    def of(cls, frame: Frame, n_points: int, rng: np.random.Generator) -> "SampledFrame":
        u, v, d = sample_depth_pixels(frame.depth, n_points, rng)
        return cls(frame, backproject(u, v, d, frame.K))

    def overlap_with(self, dst: Frame) -> float:
        u, v, z = reproject(self.points, relative_pose(self.frame.pose, dst.pose), dst.K)
        w, h = dst.size
        return overlap_fraction(u, v, z, w, h)


def overlap(src_frame: Frame, dst_frame: Frame, n_points: int = DEFAULT_POINTS,
            rng: Optional[np.random.Generator] = None) -> float:
    """Overlap of src_frame seen from dst_frame in [0, 1] (Eq. 5-6); 0 when src has no depth.

    Not symmetric: it is the share of the source's visible surface that the target also sees."""
    rng = rng if rng is not None else np.random.default_rng(0)
    return SampledFrame.of(src_frame, n_points, rng).overlap_with(dst_frame)


@dataclass
class KeyframeGroup:
    """A keyframe and the anchors found while it was the reference, in order (keyframe first)."""

    index: int
    frames: list[Frame] = field(default_factory=list)

    @property
    def keyframe(self) -> Frame:
        return self.frames[0]

    @property
    def anchors(self) -> list[Frame]:
        return self.frames[1:]

    def __len__(self) -> int:
        return len(self.frames)


class KeyframeGrouper:
    """Algorithm 1, fed one non-blurry frame at a time.

    `add(frame)` returns the role given to the frame ("keyframe", "anchor" or "garbage") and
    `completed` (a list) receives each group as soon as a new keyframe closes it; `finish()`
    closes and returns the last one. Use `feed(frames)` for a generator of completed groups.
    A frame that becomes keyframe or anchor is decoded then (its depth is needed as a source);
    if that fails (FrameError), the grouper's state is left untouched and the error propagates.
    """

    def __init__(self, t_key: float = DEFAULT_T_KEY, t_anchor: float = DEFAULT_T_ANCHOR,
                 n_points: int = DEFAULT_POINTS, seed: int = 0):
        if not 0.0 <= t_key <= 1.0 or not 0.0 <= t_anchor <= 1.0:
            raise ValueError("overlap thresholds are fractions in [0, 1]")
        self.t_key = t_key
        self.t_anchor = t_anchor
        self.n_points = n_points
        self.rng = np.random.default_rng(seed)
        self._keyframe: Optional[SampledFrame] = None
        self._anchor: Optional[SampledFrame] = None
        self._group: Optional[KeyframeGroup] = None
        self._next_index = 0
        self.completed: list[KeyframeGroup] = []
        self.n_keyframes = 0
        self.n_anchors = 0
        self.n_garbage = 0

    def _sample(self, frame: Frame) -> SampledFrame:
        frame.load()  # keyframes and anchors go on to detection: decode now, before any state change
        return SampledFrame.of(frame, self.n_points, self.rng)

    def _start_group(self, sampled: SampledFrame) -> None:
        # Algorithm 1 lines 2-3 and 11-12: keyframe, anchor = [frame] * 2; group = [keyframe]
        if self._group is not None:
            self.completed.append(self._group)
        self._keyframe = self._anchor = sampled
        self._group = KeyframeGroup(self._next_index, [sampled.frame])
        self._next_index += 1
        self.n_keyframes += 1

    def add(self, frame: Frame) -> str:
        if self._keyframe is None or self._anchor is None or self._group is None:   # set together
            self._start_group(self._sample(frame))
            return "keyframe"
        overlap_key = self._keyframe.overlap_with(frame)
        if overlap_key < self.t_key:
            self._start_group(self._sample(frame))
            return "keyframe"
        if self._anchor is self._keyframe:
            overlap_anchor = overlap_key  # same source, same samples: the same number
        else:
            overlap_anchor = self._anchor.overlap_with(frame)
        if overlap_anchor < self.t_anchor:
            self._anchor = self._sample(frame)
            self._group.frames.append(frame)
            self.n_anchors += 1
            return "anchor"
        self.n_garbage += 1
        return "garbage"

    def finish(self) -> Optional[KeyframeGroup]:
        """Close the open group (the last keyframe and its anchors) and return it."""
        group, self._group = self._group, None
        self._keyframe = self._anchor = None
        return group

    def feed(self, frames: Iterable[Frame]) -> Iterator[KeyframeGroup]:
        """Run Algorithm 1 over non-blurry frames, yielding each group once it is complete."""
        for frame in frames:
            self.add(frame)
            while self.completed:
                yield self.completed.pop(0)
        last = self.finish()
        if last is not None:
            yield last
