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
# A wall's face is a large flat area, however many pixels saw it: the fitted plane's points
# cover at least WALL_FIT_MIN_AREA_M2 of FILL_CELL_M cells (a metre square: a wall the camera
# walked past shows metres of it, a strip of furniture front seen between things far less).
# Point normals from noisy depth spread a wall's votes over many angle bins; their mean
# direction agrees with the fitted plane within WALL_NORMAL_AGREE_DEG (a line crossing a wall at
# a slant does not). A fitted plane within WALL_SAME_DEG of a wall found before that comes within
# WALL_SAME_M of it where its points lie is that wall (`same_wall`: walls of one room are never
# parallel and this close, and do not cross).
WALL_FIT_MIN_AREA_M2 = 1.0
WALL_FIT_MIN_VOTES = 30
WALL_FIT_CANDIDATES = 40
WALL_FIT_SLABS_M = (0.15, 0.10, 0.05)
WALL_NORMAL_AGREE_DEG = 5.0
WALL_SAME_DEG = 10.0
WALL_SAME_M = 0.25
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


def plane_votes(q: np.ndarray, nq: np.ndarray) -> tuple[np.ndarray, float]:
    """The Hough vote of vertical points for the planes through them: each point votes for the
    plane of its own normal's horizontal direction (WALL_ANGLE_BIN_DEG bins) through it (offset
    in WALL_OFFSET_BIN_M bins from the least offset, returned), summed over 3 x 3 bins."""
    theta = np.mod(np.arctan2(nq[:, 1], nq[:, 0]), np.pi)
    rho = q[:, 0] * np.cos(theta) + q[:, 1] * np.sin(theta)
    tbin = np.floor(np.degrees(theta) / WALL_ANGLE_BIN_DEG).astype(int)
    rmin = float(rho.min())
    rbin = np.floor((rho - rmin) / WALL_OFFSET_BIN_M).astype(int)
    nt = int(180 / WALL_ANGLE_BIN_DEG)
    acc = np.zeros((nt, rbin.max() + 3))
    np.add.at(acc, (tbin % nt, rbin), 1)
    return ndimage.uniform_filter(acc, size=(3, 3), mode=("wrap", "constant")) * 9, rmin


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
    acc, rmin = plane_votes(q, nq)
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


def _angle_gap_deg(a: float, b: float) -> float:
    """Degrees between two plane normal directions (angles mod pi)."""
    return abs(((np.degrees(a - b) + 90.0) % 180.0) - 90.0)


def fitted_plane(xy: np.ndarray, theta: float, rho: float) -> tuple[float, float]:
    """A vertical plane (theta, rho) fitted by total least squares to the top-view points within
    each of WALL_FIT_SLABS_M of the previous estimate in turn (wide first, so a vote bin's
    coarse plane is pulled onto the wall); the vote's plane when the fit turns by more than
    WALL_SAME_DEG or has too few points."""
    for slab in WALL_FIT_SLABS_M:
        near = np.abs(xy[:, 0] * np.cos(theta) + xy[:, 1] * np.sin(theta) - rho) <= slab
        if np.count_nonzero(near) < 10:
            break
        q = xy[near]
        mean = q.mean(axis=0)
        _, vecs = np.linalg.eigh(np.cov((q - mean).T))
        t = float(np.mod(np.arctan2(vecs[1, 0], vecs[0, 0]), np.pi))
        if _angle_gap_deg(t, theta) > WALL_SAME_DEG:
            break
        theta, rho = t, float(mean[0] * np.cos(t) + mean[1] * np.sin(t))
    return theta, rho


def normals_agree(normals: np.ndarray, theta: float) -> bool:
    """The mean horizontal direction of the points' normals (axial mean: angles doubled) lies
    within WALL_NORMAL_AGREE_DEG of the plane's normal."""
    ang = 2.0 * np.arctan2(normals[:, 1], normals[:, 0])
    mean = 0.5 * float(np.arctan2(np.sin(ang).mean(), np.cos(ang).mean()))
    return _angle_gap_deg(mean, theta) <= WALL_NORMAL_AGREE_DEG


def seen_face_area(along: np.ndarray, height: np.ndarray) -> float:
    """m^2 of the FILL_CELL_M cells (along the plane x height) that hold a point."""
    cells = np.floor(np.stack([along, height], axis=1) / FILL_CELL_M).astype(int)
    return len(np.unique(cells, axis=0)) * FILL_CELL_M ** 2


def fitted_walls(cloud: RoomCloud, found: list[Element]) -> list[Element]:
    """Rule "a wall is a large bounding face" for the walls the vote missed: depth noise spreads
    a wall's normals, so its votes never reach the vote rule's count. Vote bins (at least
    WALL_FIT_MIN_VOTES) are taken in turn, each plane fitted to the points (`fitted_plane`); a
    plane is a wall when it is none found before (`same_wall`), spans
    WALL_MIN_HEIGHT and WALL_MIN_LENGTH, its seen face covers WALL_FIT_MIN_AREA_M2
    (`seen_face_area`), its points' normals agree with it (`normals_agree`), and it bounds the
    room for sure: at most WALL_MAX_BEHIND of the room's points behind it and WALL_SURE_FAR more
    than WALL_FAR_M behind (a furniture front has the wall behind it). A plane found to be no wall
    votes no more (`rejected_votes`): a large front near the camera (a bed's side seen from a
    robot's height) spreads its noisy normals over many bins, and each would fit onto that same
    front again, leaving the far walls untried."""
    p, n = cloud.points, cloud.normals
    vert = (np.abs(n[:, 2]) < WALL_NORMAL_COS) & (np.linalg.norm(n[:, :2], axis=1) > 0.5)
    q, nq = p[vert], n[vert]
    planes = [e.plane for e in found if e.plane is not None]
    taken = np.zeros(len(q), bool)
    for th, rh in planes:
        taken |= np.abs(q[:, 0] * np.cos(th) + q[:, 1] * np.sin(th) - rh) <= WALL_SLAB_M
    cams = np.array([v.pose[:3, 3] @ cloud.basis.T for v in cloud.views])
    sample = p[:: max(1, len(p) // 200000)]
    out: list[Element] = []
    rejected = np.zeros(len(q), bool)
    while len(found) + len(out) < MAX_WALLS and np.count_nonzero(~taken & ~rejected) >= WALL_FIT_MIN_VOTES:
        wall = None
        for _ in range(WALL_FIT_CANDIDATES):
            free = ~taken & ~rejected
            if np.count_nonzero(free) < WALL_FIT_MIN_VOTES:
                break
            acc, rmin = plane_votes(q[free], nq[free])
            tb, rb = (int(v) for v in np.unravel_index(int(np.argmax(acc)), acc.shape))
            if acc[tb, rb] < WALL_FIT_MIN_VOTES:
                break
            line = ((tb + 0.5) * np.radians(WALL_ANGLE_BIN_DEG), rmin + (rb + 0.5) * WALL_OFFSET_BIN_M)
            wall = _fitted_wall((q, nq), taken, planes, cams, sample, line)
            if wall is not None:
                break
            rejected |= rejected_votes((q, nq), free, line)
        if wall is None or wall.plane is None:
            break
        th, rh = wall.plane
        taken |= np.abs(q[:, 0] * np.cos(th) + q[:, 1] * np.sin(th) - rh) <= WALL_SLAB_M
        planes.append((th, rh))
        out.append(wall)
    return out


def rejected_votes(vertical: tuple[np.ndarray, np.ndarray], free: np.ndarray, line: tuple[float, float]) -> np.ndarray:
    """The vertical points (`vertical`: points and normals; of those still `free` to vote) that a
    plane found to be no wall takes out of the vote: those within WALL_SLAB_M of the voted `line`
    (theta, rho) or of the plane fitted from it (`fitted_plane`), and those that voted for the
    line's bin (`plane_votes` sums 3 x 3 bins), so no rejected bin comes up again."""
    q, nq = vertical
    th, rh = fitted_plane(q[free, :2], *line)
    near = np.zeros(len(q), bool)
    for t, r in (line, (th, rh)):
        near |= np.abs(q[:, 0] * np.cos(t) + q[:, 1] * np.sin(t) - r) <= WALL_SLAB_M
    own = np.mod(np.arctan2(nq[:, 1], nq[:, 0]), np.pi)
    own_rho = q[:, 0] * np.cos(own) + q[:, 1] * np.sin(own)
    voted = ((_angle_gap_deg_all(own, line[0]) <= 1.5 * WALL_ANGLE_BIN_DEG)
             & (np.abs(own_rho - line[1]) <= 1.5 * WALL_OFFSET_BIN_M))
    return (near | voted) & free


def _angle_gap_deg_all(a: np.ndarray, b: float) -> np.ndarray:
    """Degrees between plane normal directions `a` (angles mod pi) and `b`."""
    return np.abs(((np.degrees(a - b) + 90.0) % 180.0) - 90.0)


def _fitted_wall(vertical: tuple[np.ndarray, np.ndarray], taken: np.ndarray, planes: list, cams: np.ndarray,
                 sample: np.ndarray, line: tuple[float, float]) -> Optional[Element]:
    """The wall fitted to the vertical points (`vertical`: points and normals, `taken` by walls
    found) near the voted `line` (theta, rho), or None when it is no wall (`planes`: the walls'
    lines so far; `cams`: the views' positions; `sample`: the room's points)."""
    q, nq = vertical
    th, rh = fitted_plane(q[~taken, :2], *line)
    inl = (np.abs(q[:, 0] * np.cos(th) + q[:, 1] * np.sin(th) - rh) <= WALL_SLAB_M) & ~taken
    if np.count_nonzero(inl) < WALL_FIT_MIN_VOTES or not normals_agree(nq[inl], th):
        return None
    pts = q[inl]
    if any(same_wall(pts[:, :2], th, plane) for plane in planes):
        return None
    along = -pts[:, 0] * np.sin(th) + pts[:, 1] * np.cos(th)
    a_lo, a_hi = np.percentile(along, [2, 98])
    h_lo, h_hi = np.percentile(pts[:, 2], [2, 98])
    if h_hi - h_lo < WALL_MIN_HEIGHT or a_hi - a_lo < WALL_MIN_LENGTH or seen_face_area(along, pts[:, 2]) < WALL_FIT_MIN_AREA_M2:
        return None
    side = float(np.sign(np.median(cams[:, 0] * np.cos(th) + cams[:, 1] * np.sin(th)) - rh)) or 1.0
    s_off = side * (sample[:, 0] * np.cos(th) + sample[:, 1] * np.sin(th) - rh)
    far = float(np.mean(s_off < -WALL_FAR_M))
    if float(np.mean(s_off < -WALL_SLAB_M)) > WALL_MAX_BEHIND or far > WALL_SURE_FAR:
        return None
    return Element("wall", np.min(pts, axis=0), np.max(pts, axis=0), int(inl.sum()), 0, plane=(th, rh), side=side,
                   far_behind=far)


def same_wall(xy: np.ndarray, theta: float, found: tuple[float, float]) -> bool:
    """Rule "walls do not cross": a plane (its points' top view `xy`, normal angle `theta`) within
    WALL_SAME_DEG of a found wall's (`found`: theta, rho) that comes within WALL_SAME_M of it
    where its points lie is that wall (its noisy remainder, or a slant across it): walls of one
    room are never parallel and this close, and meet only at corners, at large angles."""
    t, r = found
    if _angle_gap_deg(theta, t) > WALL_SAME_DEG:
        return False
    return float(np.min(np.abs(xy[:, 0] * np.cos(t) + xy[:, 1] * np.sin(t) - r), initial=np.inf)) <= WALL_SAME_M


def room_structure(cloud: RoomCloud) -> list[Element]:
    """Floor, walls (the vote's, then the fitted ones it missed) and horizontal surfaces."""
    found = [e for e in [floor_element(cloud)] if e is not None]
    voted = walls(cloud)
    return found + voted + fitted_walls(cloud, voted) + horizontal_surfaces(cloud)
