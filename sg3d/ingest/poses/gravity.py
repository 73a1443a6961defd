"""The room's up direction and floor height, from depth alone.

Poses of RGB-D sequences live in an arbitrary world frame (7-Scenes' is tilted ~30 degrees from
the floor), while "on", "under", heights and sizes need gravity. Rooms are full of horizontal
surfaces (floor, tables, counters, shelves, seats) and a handheld or robot camera is held
roughly upright, so:

1. prior: the cameras' image-up direction (-y of the camera) in world coordinates, averaged over
   the frames; it fixes the sign (up points against gravity) and picks horizontal surfaces over
   walls, which are just as planar;
2. surface normals from the depth image (cross product of neighbouring back-projected points on
   a subsampled grid, vectorised), rotated to world;
3. up = the dominant direction among normals within 35 degrees of the prior, refined by
   repeatedly averaging the normals within 10 degrees of the current estimate (a mean-shift on
   the sphere). Every horizontal plane votes, not only the biggest one, so it works whether the
   view is dominated by floor, table or counter, and it is deterministic (no RANSAC draws);
   a camera held over a desk looks further down than that cone, so the dense directions up to
   60 degrees from the prior are weighed too, and the one square to the cameras' image x-axes
   wins (`level_camera_up`: cameras are held without roll);
4. floor: heights (p . up) of points on horizontal surfaces; the lowest height bin holding a
   real share of them, at least `MIN_FLOOR_DROP` below the cameras, is the floor candidate: nothing
   was seen below it. It is the floor when it is what the room stands on, not a top the cameras
   were held over (`floor_not_a_top`); otherwise the recording never saw the floor (None).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable, Optional

import numpy as np

from sg3d.core.geometry import DIRECTION_DECIMALS, fixed_precision
from sg3d.core.model import vec3
from sg3d.ingest.readers.frames import Frame, FrameError

if TYPE_CHECKING:
    from sg3d.ingest.readers.base import Sequence

PRIOR_CONE_DEG = 35.0
WIDE_CONE_DEG = 60.0        # `level_camera_up`: a desk scan's top lies this far from the image-up
MODE_SHARE = 0.5
REFINE_CONE_DEG = 10.0
GRID_STRIDE = 4
MAX_RANGE_M = 5.0
# The floor lies at least this far below the average camera: a robot's camera rides 0.2-0.5 m up.
MIN_FLOOR_DROP = 0.15
# Rule "a floor, not a top": nobody holds a camera this far over a desk or table top without the
# floor in view, while a tabletop scan holds it 0.3-0.7 m over the top, looking down onto it. A
# level nearer the cameras is the floor when the cameras look along it (a robot's camera looks
# ahead, its axis within LEVEL_GAZE_DEG of the horizon on the median frame) or when it runs on
# further than any top one scans (desks 1.2-1.8 m, most tables under 2 m).
HANDHELD_DROP_M = 0.9
LEVEL_GAZE_DEG = 25.0
FLOOR_MIN_SPAN_M = 2.0
FLOOR_BIN_M = 0.02
FLOOR_MIN_SHARE = 0.01      # of all points on horizontal surfaces


@dataclass(frozen=True)
class Gravity:
    up: tuple[float, float, float]              # unit vector, world frame, against gravity
    floor_height: Optional[float]               # p . up of the floor plane; None when not seen
    camera_prior: tuple[float, float, float]    # mean image-up of the cameras
    n_normals: int                              # normals that voted for `up`

    def height(self, point: Iterable[float]) -> float:
        """Height of a world point above the floor (above the origin's level without a floor)."""
        h = float(np.dot(np.asarray(point, dtype=np.float64), self.up))
        return h - (self.floor_height or 0.0)


def camera_up_prior(frames: Iterable[Frame]) -> np.ndarray:
    """Mean over frames of the camera's image-up (-y_cam) in world coordinates, unit length."""
    ups = np.array([-f.pose[:3, 1] for f in frames])
    m = ups.mean(axis=0)
    return m / np.linalg.norm(m)


def depth_normals(frame: Frame, stride: int = GRID_STRIDE) -> tuple[np.ndarray, np.ndarray]:
    """World points and unit normals (both Nx3) on a stride-subsampled grid of the depth image."""
    d = frame.depth[::stride, ::stride].astype(np.float64)
    h, w = d.shape
    v, u = np.mgrid[0:h, 0:w]
    u = u * stride
    v = v * stride
    K = frame.K
    cam = np.stack([(u - K[0, 2]) / K[0, 0] * d, (v - K[1, 2]) / K[1, 1] * d, d], axis=-1)
    dx = cam[1:-1, 2:] - cam[1:-1, :-2]
    dy = cam[2:, 1:-1] - cam[:-2, 1:-1]
    n = np.cross(dx, dy)
    centre = d[1:-1, 1:-1]
    ok = (centre > 0) & (centre < MAX_RANGE_M)
    for nb in (d[1:-1, 2:], d[1:-1, :-2], d[2:, 1:-1], d[:-2, 1:-1]):
        # a neighbour across a depth edge gives a meaningless normal
        ok &= (nb > 0) & (np.abs(nb - centre) < 0.05 * centre + 0.02)
    norm = np.linalg.norm(n, axis=-1)
    ok &= norm > 0
    n = n[ok] / norm[ok][:, None]
    p = cam[1:-1, 1:-1][ok]
    R, t = frame.pose[:3, :3], frame.pose[:3, 3]
    return p @ R.T + t, n @ R.T


def _mean_direction(vectors: np.ndarray) -> np.ndarray:
    m = vectors.mean(axis=0)
    return m / np.linalg.norm(m)


def estimate_gravity(frames: Iterable[Frame], stride: int = GRID_STRIDE) -> Gravity:
    """Up direction and floor height from a handful of frames (10-30 spread over the sequence).
    Frames whose depth cannot be decoded are left out; ValueError when none has depth."""
    frames = list(frames)
    prior = camera_up_prior(frames)
    points, normals = [], []
    for f in frames:
        try:
            p, n = depth_normals(f, stride)
        except FrameError:
            continue
        points.append(p)
        normals.append(n)
    if not normals or sum(len(n) for n in normals) == 0:
        raise ValueError("no frame with usable depth to estimate gravity from")
    P = np.concatenate(points)
    N = np.concatenate(normals)
    N = N * np.sign(N @ prior)[:, None]  # orient every normal to the prior's side
    horizontal = N @ prior > np.cos(np.radians(PRIOR_CONE_DEG))
    up = prior if not horizontal.any() else _mean_shift(N[horizontal], _mean_direction(N[horizontal]))
    up = level_camera_up(up, N, prior, frames)
    used = int(np.count_nonzero(N @ up > np.cos(np.radians(REFINE_CONE_DEG))))
    # kept to a fixed precision (`fixed_precision`): every later stage measures in this frame,
    # and another CPU's BLAS leaves other last bits in `up`
    up = fixed_precision(up, DIRECTION_DECIMALS)
    floor = _floor_height(P, N, up, frames)
    return Gravity(vec3(up), None if floor is None else float(fixed_precision(floor)), vec3(prior), used)


def _mean_shift(cand: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Repeatedly the mean of the normals within REFINE_CONE_DEG of the estimate."""
    up = start
    cos_refine = np.cos(np.radians(REFINE_CONE_DEG))
    for _ in range(10):
        near = cand @ up > cos_refine
        if not near.any():
            break
        new = _mean_direction(cand[near])
        converged = float(new @ up) > 1 - 1e-10
        up = new
        if converged:
            break
    return up


def level_camera_up(up: np.ndarray, N: np.ndarray, prior: np.ndarray, frames: list[Frame]) -> np.ndarray:
    """Rule "cameras are held level": a camera held over a desk looks 40-60 degrees down, so the
    top's normals lie that far from the cameras' image-up, beyond PRIOR_CONE_DEG, and the wall
    behind the desk is as far on the other side. Every dense direction within WIDE_CONE_DEG of the
    prior (a mean-shift from every 32nd normal of a sample there not already near one) holding MODE_SHARE of the densest one's
    normals is a candidate, `up` among them; up is the candidate most nearly square to the
    cameras' image x-axes (median |x . up|), since people and robots hold a camera without
    rolling it; `up` stays on a tie and when it is the only one."""
    cos_refine = np.cos(np.radians(REFINE_CONE_DEG))
    wide = N[N @ prior > np.cos(np.radians(WIDE_CONE_DEG))]
    if len(wide) == 0:
        return up
    cand = wide[:: max(1, len(wide) // 5000)]        # the modes are as plain in a sample
    modes = [up]
    for seed in cand[:: max(1, len(cand) // 32)]:
        if any(float(seed @ o) > cos_refine for o in modes):
            continue                                   # it would climb to a mode already found
        m = _mean_shift(cand, seed)
        if all(float(m @ o) <= cos_refine for o in modes):
            modes.append(m)
    support = [int(np.count_nonzero(cand @ m > cos_refine)) for m in modes]
    xs = np.array([f.pose[:3, 0] for f in frames])
    if max(support) == 0:
        return up
    options = [(float(np.median(np.abs(xs @ m))), k) for k, m in enumerate(modes) if support[k] >= MODE_SHARE * max(support)]
    best = min(options)[1]
    return up if best == 0 else _mean_shift(wide, modes[best])


def _floor_height(P: np.ndarray, N: np.ndarray, up: np.ndarray, frames: list[Frame]) -> Optional[float]:
    flat = N @ up > np.cos(np.radians(REFINE_CONE_DEG))
    if np.count_nonzero(flat) < 100:
        return None
    heights = P[flat] @ up
    cameras = float(np.mean([f.pose[:3, 3] @ up for f in frames]))
    below = heights[heights < cameras - MIN_FLOOR_DROP]
    if below.size < max(100, 0.02 * heights.size):
        return None
    edges = np.arange(below.min(), below.max() + 2 * FLOOR_BIN_M, FLOOR_BIN_M)
    counts, edges = np.histogram(below, bins=edges)
    # support of each level = points within +-2 bins; the floor is the lowest level holding a
    # real share of all horizontal points (stray low points are depth noise or reflections)
    support = np.convolve(counts, np.ones(5, dtype=int), mode="same")
    strong = np.flatnonzero(support >= max(100, FLOOR_MIN_SHARE * heights.size))
    if strong.size == 0:
        return None
    k = int(strong[0])
    k = k + int(np.argmax(counts[k:k + 5]))  # the densest bin of that level
    lo, hi = edges[max(0, k - 2)], edges[min(len(edges) - 1, k + 3)]
    level = (heights >= lo) & (heights <= hi) & (heights < cameras - MIN_FLOOR_DROP)
    floor = float(np.median(heights[level]))
    gaze = float(np.median([np.degrees(np.arcsin(np.clip(-f.pose[:3, 2] @ up, -1, 1))) for f in frames]))
    return floor if floor_not_a_top(P[flat][level], up, cameras - floor, gaze) else None


def horizontal_span(points: np.ndarray, up: np.ndarray) -> float:
    """The longer of a level's 2-98 percentile extents along two horizontal axes."""
    e1 = np.cross(up, (1.0, 0.0, 0.0) if abs(up[0]) < 0.9 else (0.0, 1.0, 0.0))
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    along = points @ np.stack([e1, e2], axis=1)
    lo, hi = np.percentile(along, [2, 98], axis=0)
    return float(np.max(hi - lo))


def floor_not_a_top(level_points: np.ndarray, up: np.ndarray, drop: float, gaze_deg: float) -> bool:
    """Rule "a floor, not a top": the lowest level seen is the floor when it lies at least
    HANDHELD_DROP_M below the average camera, when the cameras look along it (`gaze_deg`, the
    median camera axis's angle below the horizon, under LEVEL_GAZE_DEG) or when it spans at least
    FLOOR_MIN_SPAN_M (`horizontal_span`); a nearer, smaller level the cameras looked down onto
    is a top they were held over (a desk scan), and the floor was not seen."""
    return (drop >= HANDHELD_DROP_M or gaze_deg < LEVEL_GAZE_DEG
            or horizontal_span(level_points, up) >= FLOOR_MIN_SPAN_M)


def estimate_up(frames: Iterable[Frame], stride: int = GRID_STRIDE) -> np.ndarray:
    """The room's up direction (unit 3-vector, world frame, pointing against gravity)."""
    return np.asarray(estimate_gravity(frames, stride).up)


def sample_frames(seq: Sequence, n: int = 20, start: int = 0, stop: Optional[int] = None) -> list[Frame]:
    """n readable frames spread evenly over a sequence, or over its frames [start, stop) (for
    estimate_gravity)."""
    out = []
    stop = len(seq) if stop is None else min(stop, len(seq))
    for i in np.linspace(start, stop - 1, min(n, stop - start)).round().astype(int):
        try:
            out.append(seq.frame(int(i)))
        except FrameError:
            continue
    return out
