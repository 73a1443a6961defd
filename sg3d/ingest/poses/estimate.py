"""Camera poses of an RGB-D sequence that comes without them.

1. tracking: RGB-D odometry from the last placed frame to every `step`-th frame; when a fit
   fails, the frames in between are tried one by one, and a frame no neighbour confirms is left
   unplaced with the reason. After `MAX_MISSES` unplaced frames in a row the track is lost and a
   new segment starts (a lost track never chains a wrong motion into the map);
2. keyframes (every ~0.15 m or 12 degrees), each fitted straight to the previous two (drift then
   grows per keyframe, not per tracked frame), and loop closures: a keyframe near an older one of
   the same track (by the current estimate) is fitted to it, starting from the estimate. A fit
   is accepted when half of the depth overlaps the other view, 85 % of that agrees within 3 cm,
   and it is consistent with the drift the odometry can have;
3. segments are linked by fitting their first and last keyframes to the keyframes of the others
   that look most alike; the largest linked group is the map, the rest is left unplaced;
4. the pose graph (odometry + closure + link edges) is optimised (GTSAM), and the frames between
   tracked ones take poses interpolated along the trajectory (Slerp).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.ingest.poses.closure import LOOP_MIN_AGREEMENT, LOOP_MIN_OVERLAP, loop_edges, neighbour_edges
from sg3d.ingest.poses.graph import optimise_pose_graph
from sg3d.ingest.poses.tracking import Odometry, View, motion_gap, similarity
from sg3d.ingest.poses.trajectory import interpolate_poses, path_length
from sg3d.ingest.readers.frames import FrameError

DEFAULT_STEP = 4             # odometry on every 4th frame (measured: benchmarks/bench_poses.py)
TRACK_MIN_INLIERS = 0.5      # share of depth a frame-to-frame fit must confirm
LOOP_MIN_INLIERS = 0.6       # stricter for segment links
MAX_MISSES = 6               # unplaced frames in a row that end a segment
MIN_SEGMENT_FRAMES = 10      # a shorter segment is not trusted on its own
KEYFRAME_M, KEYFRAME_DEG = 0.15, 12.0
LINK_CANDIDATES = 4

Loader = Callable[[int], tuple[np.ndarray, np.ndarray]]   # index -> (depth metres, grey image)


@dataclass
class _Segment:
    start: int
    processed: list[int] = field(default_factory=list)
    keyframes: list[View] = field(default_factory=list)
    last: Optional[View] = None

    @property
    def span(self) -> int:
        return self.processed[-1] - self.processed[0] + 1 if self.processed else 0


@dataclass
class PoseEstimate:
    """Estimated camera-to-world poses (world = the first placed camera) and what happened."""
    poses: dict[int, np.ndarray]
    unplaced: dict[int, str]
    processed: int
    keyframes: int
    loop_closures: int
    segments: int
    linked_segments: int
    seconds: float

    @property
    def length_m(self) -> float:
        return path_length(np.array([self.poses[i] for i in sorted(self.poses)])) if self.poses else 0.0


class _Estimator:
    def __init__(self, n: int, load: Loader, K: np.ndarray, size: tuple[int, int], step: int,
                 progress: Optional[Callable[[int, int], None]]):
        self.n, self.load, self.step, self.progress = n, load, step, progress
        self.odometry = Odometry(K, size)
        self.poses: dict[int, np.ndarray] = {}
        self.unplaced: dict[int, str] = {}
        self.edges: list[tuple[int, int, np.ndarray, bool]] = []
        self.segments: list[_Segment] = []
        self.loops = 0
        self.processed = 0

    def view(self, j: int) -> Optional[View]:
        try:
            depth, gray = self.load(j)
            return self.odometry.view(j, depth, gray)
        except FrameError as exc:
            self.unplaced[j] = exc.reason
        except ValueError as exc:
            self.unplaced[j] = f"cannot be tracked: {exc}"
        return None

    # -- 1. tracking ---------------------------------------------------------------------------
    def track(self) -> None:
        ref: Optional[View] = None
        seg: Optional[_Segment] = None
        j, stride, fine_until, misses = 0, self.step, -1, 0
        while j < self.n:
            if self.progress:
                self.progress(j, self.n)
            cur = self.view(j)
            self.processed += 1
            if cur is None:
                if ref is not None and stride > 1 and j - ref.index > 1:   # try the frames in between
                    stride, fine_until, j = 1, j, ref.index + 1
                    continue
                if ref is not None:
                    misses += 1
                    if misses >= MAX_MISSES:
                        j, ref, misses = ref.index + 1, None, 0
                        continue
                j += 1
                continue
            if ref is None:      # a new segment starts here
                seg = _Segment(j)
                self.segments.append(seg)
                self._place(seg, cur, np.eye(4), None)
                ref, stride, misses = cur, self.step, 0
                j = self._next(j, stride)
                continue
            fit = self.odometry.fit(cur, ref, TRACK_MIN_INLIERS)
            if fit.ok:
                assert seg is not None     # a segment is open whenever there is a reference frame
                self._place(seg, cur, self.poses[ref.index] @ fit.motion, ref.index, fit.motion)
                ref, misses = cur, 0
                if stride == 1 and j >= fine_until:
                    stride = self.step
                j = self._next(j, stride)
            elif j - ref.index > 1:          # retry the frames in between one by one
                stride, fine_until, j = 1, j, ref.index + 1
            else:
                self.unplaced[j] = f"cannot be tracked: {fit.why}"
                misses += 1
                if misses >= MAX_MISSES:
                    j, ref, misses = ref.index + 1, None, 0
                else:
                    j += 1
        if self.progress:
            self.progress(self.n, self.n)

    def _next(self, j: int, stride: int) -> int:
        """The next frame to track; the sequence's last frame is always tracked."""
        return j + stride if j + stride < self.n or j == self.n - 1 else self.n - 1

    def _place(self, seg: _Segment, view: View, pose: np.ndarray, ref: Optional[int],
               motion: Optional[np.ndarray] = None) -> None:
        self.unplaced.pop(view.index, None)
        self.poses[view.index] = pose
        seg.processed.append(view.index)
        seg.last = view
        if ref is not None:
            assert motion is not None      # a frame placed from a reference comes with its motion
            self.edges.append((ref, view.index, motion, False))
        last = seg.keyframes[-1] if seg.keyframes else None
        if last is None or _far(self.poses[last.index], pose, KEYFRAME_M, KEYFRAME_DEG):
            self._link_keyframes(seg, view)
            self._close_loops(seg, view)
            seg.keyframes.append(view)

    # -- 2. keyframe edges and loop closures (`sg3d.ingest.poses.closure`) ---------------------------
    def _link_keyframes(self, seg: _Segment, view: View) -> None:
        self.edges.extend(neighbour_edges(self.odometry, view, self.poses, seg.keyframes))

    def _close_loops(self, seg: _Segment, view: View) -> None:
        found = loop_edges(self.odometry, view, self.poses, seg.keyframes)
        self.edges.extend(found)
        self.loops += len(found)

    # -- 3. segments -----------------------------------------------------------------------------
    def link_segments(self) -> list[_Segment]:
        """Drop segments too short to trust, link the rest; the segments of the biggest group."""
        kept = []
        for seg in self.segments:
            if seg.span < MIN_SEGMENT_FRAMES:
                for i in self._frames_of(seg):
                    self.poses.pop(i, None)
                    self.unplaced[i] = (f"tracking lost: only {seg.span} frames from here could be tracked together "
                                        f"(at least {MIN_SEGMENT_FRAMES} are needed to trust them)")
            else:
                kept.append(seg)
        if not kept:
            return []
        group = list(range(len(kept)))

        def root(a: int) -> int:
            while group[a] != a:
                a = group[a]
            return a

        self.linked = 0
        for b in range(1, len(kept)):
            for a in range(b - 1, -1, -1):
                if root(a) != root(b) and self._link(kept[a], kept[b], resumed=a == b - 1):
                    group[root(b)] = root(a)
                    self.linked += 1
        sizes: dict[int, int] = {}
        for k, seg in enumerate(kept):
            sizes[root(k)] = sizes.get(root(k), 0) + seg.span
        main = max(sizes, key=lambda r: (sizes[r], -r))
        chosen = [seg for k, seg in enumerate(kept) if root(k) == main]
        for k, seg in enumerate(kept):
            if root(k) != main:
                for i in self._frames_of(seg):
                    self.poses.pop(i, None)
                    self.unplaced[i] = (f"tracking lost before frame {seg.start} and the {seg.span} frames from "
                                        f"there could not be linked to the main track")
        return chosen

    def _frames_of(self, seg: _Segment) -> list[int]:
        """Every frame a segment spans that has no reason of its own for being unplaced."""
        span = range(seg.processed[0], seg.processed[-1] + 1)
        return [i for i in span if i in seg.processed or i not in self.unplaced]

    def _extrapolate(self, seg: _Segment, t: int) -> np.ndarray:
        """The pose at frame t if the camera kept the mean velocity of the segment's last steps."""
        idx = seg.processed
        a, b = idx[max(0, len(idx) - 6)], idx[-1]
        if a == b:
            return self.poses[b]
        rel = np.linalg.inv(self.poses[a]) @ self.poses[b]
        scale = (t - b) / (b - a)
        step = np.eye(4)
        step[:3, :3] = Rotation.from_rotvec(Rotation.from_matrix(rel[:3, :3]).as_rotvec() * scale).as_matrix()
        step[:3, 3] = rel[:3, 3] * scale
        return self.poses[b] @ step

    def _link(self, a: _Segment, b: _Segment, resumed: bool = False) -> bool:
        """Place segment b in segment a's frame: when b follows a (`resumed`), fit b's first view
        to a's last one from where a's motion would have taken the camera (or from where it
        stood); then b's first and last keyframes to a's keyframes that look most alike. On
        success move b's poses into a's frame and record the link edge."""
        if resumed and a.last is not None and b.keyframes:
            query = b.keyframes[0]
            for guess in (self._extrapolate(a, query.index), self.poses[a.last.index]):
                predicted = np.linalg.inv(self.poses[a.last.index]) @ guess
                fit = self.odometry.fit_from(query, a.last, predicted, LOOP_MIN_OVERLAP, LOOP_MIN_AGREEMENT)
                if fit.ok:
                    self._move(b, query, a.last, fit.motion)
                    return True
        for query in {id(v): v for v in (b.keyframes[:2] + b.keyframes[-2:])}.values():
            ranked = sorted(a.keyframes, key=lambda kf: -similarity(query, kf))[:LINK_CANDIDATES]
            for kf in ranked:
                fit = self.odometry.fit(query, kf, LOOP_MIN_INLIERS)
                if fit.ok:
                    self._move(b, query, kf, fit.motion)
                    return True
        return False

    def _move(self, b: _Segment, query: View, anchor: View, motion: np.ndarray) -> None:
        move = self.poses[anchor.index] @ motion @ np.linalg.inv(self.poses[query.index])
        for i in b.processed:
            self.poses[i] = move @ self.poses[i]
        self.edges.append((anchor.index, query.index, motion, True))

    # -- 4. optimisation and interpolation ---------------------------------------------------------
    def finish(self, segments: list[_Segment], times: list[float]) -> dict[int, np.ndarray]:
        if not segments:
            return {}
        nodes = {i for seg in segments for i in seg.processed}
        edges = [e for e in self.edges if e[0] in nodes and e[1] in nodes]
        optimised = optimise_pose_graph({i: self.poses[i] for i in nodes}, edges, anchor=segments[0].processed[0])
        anchor_fix = np.linalg.inv(optimised[segments[0].processed[0]])
        out: dict[int, np.ndarray] = {}
        for seg in segments:
            idx = seg.processed
            known = np.array([anchor_fix @ optimised[i] for i in idx])
            between = [k for k in range(idx[0], idx[-1] + 1) if k not in self.unplaced]
            poses = interpolate_poses([times[i] for i in idx], known, [times[k] for k in between])
            out.update(zip(between, poses))
        return out


def _far(a: np.ndarray, b: np.ndarray, metres: float, degrees: float) -> bool:
    gap_m, gap_deg = motion_gap(a, b)
    return gap_m > metres or gap_deg > degrees


def estimate_poses(n: int, load: Loader, camera: tuple[np.ndarray, tuple[int, int]],
                   times: Optional[list[float]] = None, step: int = DEFAULT_STEP,
                   progress: Optional[Callable[[int, int], None]] = None) -> PoseEstimate:
    """Camera-to-world poses of frames 0..n-1 (`load(i)` gives depth in metres registered to the
    grey image, raising FrameError for a bad frame); `camera`: the colour camera's K and size."""
    K, size = camera
    t0 = time.perf_counter()
    est = _Estimator(n, load, K, size, step, progress)
    est.track()
    segments = est.link_segments()
    poses = est.finish(segments, list(times) if times is not None else list(range(n)))
    unplaced = {i: why for i, why in est.unplaced.items() if i not in poses}
    for i in range(n):      # frames no segment reaches (none in practice) are named too
        if i not in poses and i not in unplaced:
            unplaced[i] = "tracking lost: not reached by any track"
    return PoseEstimate(poses, dict(sorted(unplaced.items())), est.processed,
                        sum(len(s.keyframes) for s in segments), est.loops, len(est.segments),
                        getattr(est, "linked", 0), time.perf_counter() - t0)
