"""The room's structure from its fused point cloud: floor, walls and large horizontal surfaces.

Objects stand on structure, and what is left of the cloud once structure is taken away is the
room's objects (`sg3d.ingest.discover.segments`). Each element is found by a named rule:

- floor (`floor_element`): the points of the gravity estimate's floor plane (h within
  FLOOR_SLAB_M of 0, normal up); none when the recording never saw the floor (`RoomCloud.floor_seen`);
- horizontal surfaces (`horizontal_surfaces`): levels where many upward-facing points lie
  above SURFACE_MIN_HEIGHT (peaks of the height histogram; at any height where the floor was not
  seen: a desk scan's top is its lowest level), each level's points cut into connected footprints
  of at least SURFACE_MIN_AREA, seen from several frames;
- walls (`walls`): vertical planes (a Hough vote over horizontal normal direction and offset)
  that are tall (WALL_MIN_HEIGHT), long (WALL_MIN_LENGTH) and bound the room: almost no point
  lies behind them; the other planes are fronts when their points fill them (`plane_fill`);
- a surface's name (`surface_name`) from its height and depth: counter, shelf or surface.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from scipy import ndimage

from sg3d.ingest.discover.room_cloud import RoomCloud

FLOOR_SLAB_M = 0.04
UP_NORMAL_COS = 0.95                  # a normal within ~18 degrees of up faces up
SURFACE_MIN_HEIGHT = 0.25             # lower flat things are clutter on the floor, not furniture
SURFACE_SLAB_M = 0.03                 # a surface's points lie within this of its level
SURFACE_MIN_AREA = 0.10               # m^2 of footprint
SURFACE_CELL_M = 0.05
SURFACE_MIN_FRAMES = 3                # a footprint cell counts when this many frames saw it
SURFACE_PEAK_MIN_POINTS = 300
WALL_NORMAL_COS = 0.15                # |n . up| below this: a vertical surface
WALL_ANGLE_BIN_DEG = 2.0
WALL_OFFSET_BIN_M = 0.03
WALL_SLAB_M = 0.05
WALL_MIN_HEIGHT = 0.6
WALL_MIN_LENGTH = 1.0
WALL_MAX_BEHIND = 0.10                # share of the room's points that may lie behind a wall
# A wall that bounds the room for sure: at most WALL_SURE_FAR of the points lie more than
# WALL_FAR_M behind it (what a window or glass door shows of the outside).
WALL_FAR_M = 0.3
WALL_SURE_FAR = 0.01
MAX_WALLS = 10
# A front is a face (cabinet doors, a backsplash): its points fill at least FRONT_MIN_FILL of the
# FILL_CELL_M cells of its rectangle. The folds of a curtain or the bars of a frame line up on a
# plane in strips and fill far less.
FRONT_MIN_FILL = 0.45
FILL_CELL_M = 0.05
# Surface names: a counter is a deep surface at worktop height; a shelf a narrow one, or any
# surface above reach-in height; anything else a surface (a desk or table top no detector named).
COUNTER_HEIGHT = (0.75, 1.10)
COUNTER_MIN_DEPTH = 0.40
SHELF_MAX_DEPTH = 0.45
SHELF_MIN_HEIGHT = 1.10


@dataclass
class Element:
    """One element of the room's structure, gravity frame (h above the floor)."""

    label: str                        # floor | wall | counter | shelf | surface
    lo: np.ndarray                    # box corners (a, b, h)
    hi: np.ndarray
    n_points: int
    frames: int                       # frames that saw it
    height: float = 0.0               # level of a horizontal surface (its top)
    footprint: Optional[np.ndarray] = None   # bool grid of a surface, SURFACE_CELL_M cells
    origin: Optional[np.ndarray] = None      # (a, b) of footprint[0, 0]
    plane: Optional[tuple[float, float]] = None   # a wall's (angle rad, offset m)
    side: float = 1.0                 # sign of (offset along the plane normal - rho) on the room's side
    far_behind: float = 1.0           # share of the room's points more than WALL_FAR_M behind it
    _grown: Optional[np.ndarray] = field(default=None, repr=False)   # footprint grown by a cell

    def behind(self, pts: np.ndarray, margin: float) -> np.ndarray:
        """Points of a wall's far side (outside the room) by more than `margin`."""
        assert self.plane is not None
        theta, rho = self.plane
        off = pts[:, 0] * np.cos(theta) + pts[:, 1] * np.sin(theta) - rho
        return self.side * off < -margin

    def contains(self, pts: np.ndarray, slab: float) -> np.ndarray:
        """Points of this element's slab: within `slab` of its surface (its level, or its plane)."""
        if self.label == "floor":
            return np.abs(pts[:, 2]) <= slab
        if self.label in ("wall", "front"):
            assert self.plane is not None
            theta, rho = self.plane
            off = pts[:, 0] * np.cos(theta) + pts[:, 1] * np.sin(theta) - rho
            return np.abs(off) <= slab
        hit = np.zeros(len(pts), bool)
        idx = np.flatnonzero(np.abs(pts[:, 2] - self.height) <= slab)
        if idx.size == 0:
            return hit
        cells = np.floor((pts[idx, :2] - self.origin) / SURFACE_CELL_M).astype(int)
        if self._grown is None:
            self._grown = ndimage.binary_dilation(self.footprint, iterations=1)
        fp = self._grown
        inside = (cells >= 0).all(axis=1) & (cells[:, 0] < fp.shape[0]) & (cells[:, 1] < fp.shape[1])
        idx, cells = idx[inside], cells[inside]
        hit[idx] = fp[cells[:, 0], cells[:, 1]]
        return hit


def _frames(cloud: RoomCloud, mask: np.ndarray) -> int:
    return int(np.unique(cloud.frame[mask]).size)


def floor_element(cloud: RoomCloud) -> Optional[Element]:
    """Rule "floor": the points within FLOOR_SLAB_M of the floor level whose normal faces up;
    its box spans their 1-99 percentile footprint. None when fewer than 200 points, or when the
    recording never saw the floor (h = 0 is then only its lowest point)."""
    if not cloud.floor_seen:
        return None
    p, n = cloud.points, cloud.normals
    mask = (np.abs(p[:, 2]) <= FLOOR_SLAB_M) & (n[:, 2] >= UP_NORMAL_COS)
    if np.count_nonzero(mask) < 200:
        return None
    q = p[mask]
    lo = np.percentile(q, 1, axis=0)
    hi = np.percentile(q, 99, axis=0)
    lo[2], hi[2] = -0.01, 0.0
    return Element("floor", lo, hi, int(mask.sum()), _frames(cloud, mask))


def surface_name(height: float, lo: np.ndarray, hi: np.ndarray) -> str:
    """Rule "surface name": a counter is COUNTER_HEIGHT high and at least COUNTER_MIN_DEPTH deep
    (its shorter horizontal side); a shelf is narrower than SHELF_MAX_DEPTH or above
    SHELF_MIN_HEIGHT; anything else is a surface."""
    depth = float(min(hi[0] - lo[0], hi[1] - lo[1]))
    if COUNTER_HEIGHT[0] <= height <= COUNTER_HEIGHT[1] and depth >= COUNTER_MIN_DEPTH:
        return "counter"
    if depth < SHELF_MAX_DEPTH or height > SHELF_MIN_HEIGHT:
        return "shelf"
    return "surface"


def horizontal_surfaces(cloud: RoomCloud) -> list[Element]:
    """Rule "horizontal surface": peaks of the height histogram of up-facing points above
    SURFACE_MIN_HEIGHT; each level's points (within SURFACE_SLAB_M) rasterised into
    SURFACE_CELL_M cells seen by SURFACE_MIN_FRAMES frames, closed, cut into connected
    footprints of at least SURFACE_MIN_AREA. Where the floor was not seen, at any height, and
    each is a "surface": its height above the floor is unknown."""
    p, n = cloud.points, cloud.normals
    lowest = SURFACE_MIN_HEIGHT if cloud.floor_seen else float(p[:, 2].min(initial=0.0)) - 0.02
    up = (n[:, 2] >= UP_NORMAL_COS) & (p[:, 2] >= lowest)
    if np.count_nonzero(up) < SURFACE_PEAK_MIN_POINTS:
        return []
    h = p[up, 2]
    edges = np.arange(lowest, float(h.max()) + 0.02, 0.01)
    counts, _ = np.histogram(h, edges)
    smooth = np.convolve(counts, np.ones(3), mode="same")
    peaks = [k for k in range(len(smooth))
             if smooth[k] >= SURFACE_PEAK_MIN_POINTS
             and smooth[k] == smooth[max(0, k - 4):k + 5].max()]
    out: list[Element] = []
    used = np.zeros(len(p), bool)
    for k in sorted(peaks, key=lambda k: -smooth[k]):
        level = float(edges[k] + 0.005)
        sel = up & ~used & (np.abs(p[:, 2] - level) <= SURFACE_SLAB_M)
        if np.count_nonzero(sel) < SURFACE_PEAK_MIN_POINTS:
            continue
        q, f = p[sel], cloud.frame[sel]
        level = float(np.median(q[:, 2]))
        origin = q[:, :2].min(axis=0)
        cells = np.floor((q[:, :2] - origin) / SURFACE_CELL_M).astype(int)
        shape = cells.max(axis=0) + 1
        flat = cells[:, 0] * shape[1] + cells[:, 1]
        pairs = np.unique(flat * (len(cloud.views) + 1) + f)
        seen = np.bincount(pairs // (len(cloud.views) + 1), minlength=shape[0] * shape[1]).reshape(shape)
        grid = ndimage.binary_closing(seen >= SURFACE_MIN_FRAMES, iterations=2)
        labels, count = ndimage.label(grid)
        for c in range(1, count + 1):
            fp = labels == c
            if fp.sum() * SURFACE_CELL_M ** 2 < SURFACE_MIN_AREA:
                continue
            ij = np.argwhere(fp)
            lo2 = origin + ij.min(axis=0) * SURFACE_CELL_M
            hi2 = origin + (ij.max(axis=0) + 1) * SURFACE_CELL_M
            lo = np.array([lo2[0], lo2[1], level - SURFACE_SLAB_M])
            hi = np.array([hi2[0], hi2[1], level])
            el = Element(surface_name(level, lo, hi) if cloud.floor_seen else "surface", lo, hi, 0, 0, level, fp, origin)
            cand = np.flatnonzero(sel)
            member = cand[el.contains(p[cand], SURFACE_SLAB_M)]
            el.n_points, el.frames = int(member.size), int(np.unique(cloud.frame[member]).size)
            used[member] = True
            out.append(el)
    return out


def plane_fill(along: np.ndarray, height: np.ndarray) -> float:
    """Rule "a front is a face": the share of the FILL_CELL_M cells of a plane's rectangle (its
    2-98 percentile extent along the plane and in height) that hold at least one of its points."""
    a_lo, a_hi = np.percentile(along, [2, 98])
    h_lo, h_hi = np.percentile(height, [2, 98])
    inside = (along >= a_lo) & (along <= a_hi) & (height >= h_lo) & (height <= h_hi)
    cells = np.floor(np.stack([along[inside] - a_lo, height[inside] - h_lo], axis=1) / FILL_CELL_M)
    total = np.ceil((a_hi - a_lo) / FILL_CELL_M) * np.ceil((h_hi - h_lo) / FILL_CELL_M)
    return float(len(np.unique(cells.astype(int), axis=0)) / max(total, 1.0))


def walls(cloud: RoomCloud) -> list[Element]:
    """Rule "wall": the strongest vertical planes of a Hough vote (horizontal normal angle in
    WALL_ANGLE_BIN_DEG bins, offset in WALL_OFFSET_BIN_M bins) whose points span at least
    WALL_MIN_HEIGHT in height and WALL_MIN_LENGTH along the plane, with at most WALL_MAX_BEHIND
    of the room's points behind them (a wall bounds the room; a cabinet front does not). A plane
    with more behind it is a front when it is a face (`plane_fill`), and no element otherwise."""
    p, n = cloud.points, cloud.normals
    vert = (np.abs(n[:, 2]) < WALL_NORMAL_COS) & (np.linalg.norm(n[:, :2], axis=1) > 0.5)
    if np.count_nonzero(vert) < 500:
        return []
    q, nq = p[vert], n[vert]
    theta = np.mod(np.arctan2(nq[:, 1], nq[:, 0]), np.pi)
    rho = q[:, 0] * np.cos(theta) + q[:, 1] * np.sin(theta)
    tbin = np.floor(np.degrees(theta) / WALL_ANGLE_BIN_DEG).astype(int)
    rmin = float(rho.min())
    rbin = np.floor((rho - rmin) / WALL_OFFSET_BIN_M).astype(int)
    nt = int(180 / WALL_ANGLE_BIN_DEG)
    acc = np.zeros((nt, rbin.max() + 3))
    np.add.at(acc, (tbin % nt, rbin), 1)
    acc = ndimage.uniform_filter(acc, size=(3, 3), mode=("wrap", "constant")) * 9
    cams = np.array([v.pose[:3, 3] @ cloud.basis.T for v in cloud.views])
    out: list[Element] = []
    taken = np.zeros(len(q), bool)
    sample = p[:: max(1, len(p) // 200000)]
    for _ in range(MAX_WALLS * 4):
        if len(out) >= MAX_WALLS:
            break
        t, r = np.unravel_index(int(np.argmax(acc)), acc.shape)
        if acc[t, r] < 500:
            break
        acc[max(0, t - 3):t + 4, max(0, r - 3):r + 4] = 0
        th = (t + 0.5) * np.radians(WALL_ANGLE_BIN_DEG)
        rh = rmin + (r + 0.5) * WALL_OFFSET_BIN_M
        off = q[:, 0] * np.cos(th) + q[:, 1] * np.sin(th) - rh
        inl = (np.abs(off) <= WALL_SLAB_M) & ~taken
        if np.count_nonzero(inl) < 500:
            continue
        rh = rh + float(np.median(off[inl]))
        pts = q[inl]
        # its extent and its face count what a stronger plane took too (a wall's foot, the
        # wall beside a front): that plane's points still show where this one runs
        near = np.abs(off) <= WALL_SLAB_M
        along = -q[near, 0] * np.sin(th) + q[near, 1] * np.cos(th)
        a_lo, a_hi = np.percentile(along, [2, 98])
        h_lo, h_hi = np.percentile(pts[:, 2], [2, 98])
        if h_hi - h_lo < WALL_MIN_HEIGHT or a_hi - a_lo < WALL_MIN_LENGTH:
            continue
        side = np.sign(np.median(cams[:, 0] * np.cos(th) + cams[:, 1] * np.sin(th)) - rh)
        s_off = sample[:, 0] * np.cos(th) + sample[:, 1] * np.sin(th) - rh
        behind = float(np.mean(side * s_off < -WALL_SLAB_M))
        far = float(np.mean(side * s_off < -WALL_FAR_M))
        label = "wall" if behind <= WALL_MAX_BEHIND else "front"
        taken |= inl
        if label == "front" and plane_fill(along, q[near, 2]) < FRONT_MIN_FILL:
            continue           # its points are no other plane's either
        lo = np.min(pts, axis=0)
        hi = np.max(pts, axis=0)
        out.append(Element(label, lo, hi, int(inl.sum()), 0, plane=(float(th), float(rh)), side=float(side or 1.0),
                           far_behind=far))
    return out


def room_structure(cloud: RoomCloud) -> list[Element]:
    """Floor, walls and horizontal surfaces of the room."""
    found = [e for e in [floor_element(cloud)] if e is not None]
    return found + walls(cloud) + horizontal_surfaces(cloud)
