"""Class-agnostic objects: what the room's cloud holds once its structure is taken away.

The points of the fused cloud (`sg3d.ingest.discover.room_cloud`) that are not floor, wall or a horizontal
surface's slab are binned into VOXEL_M voxels; a voxel counts when MIN_VOXEL_FRAMES frames saw a
point in it (one view's flying pixels do not). Connected voxels (26-neighbourhood) are one
segment. A segment is an object candidate when its size is plausible for a household object
(`plausible_size`) and it passes the depth existence test (`depth_evidence`): in the frames that
look at its place, the depth camera sees a surface there (hits) rather than through it (free
space). A shadow, a reflection or one frame's artefact is seen through from the other views.
Segments that touch are cut apart where they meet: at necks in the top view (`split_at_necks`:
things side by side on a table; `split_at_colour_edge`: with no neck, where their colours
change) and at a wall's plane (`split_at_wall`: things standing against a
wall no structure rule found).
"""
from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
from scipy import ndimage

from sg3d.ingest.discover.room_cloud import RoomCloud
from sg3d.ingest.discover.structure import (
    FLOOR_SLAB_M,
    SURFACE_SLAB_M,
    WALL_FAR_M,
    WALL_SURE_FAR,
    Element,
)

VOXEL_M = 0.025
# Points this close to a wall or a long vertical front (cabinet doors, a backsplash) are cut
# away, so what hangs on it or stands against it comes apart from it.
PLANE_CUT_M = 0.03
MIN_VOXEL_FRAMES = 2
MIN_VOXELS = 12
# A segment rests on a surface when its bottom is this close to the surface's level (discovery's
# rules and a bookcase's boards, `shelves`).
RESTING_M = 0.05
MIN_EXTENT_M = 0.05
MAX_EXTENT_M = 2.5
MAX_HEIGHT_M = 2.6            # above that: ceiling fittings, not the room's objects
# Depth existence: a voxel is hit in a view when the depth there lies within
# HIT_TOLERANCE_M + HIT_TOLERANCE_REL * range of it, seen through when the depth lies beyond it.
HIT_TOLERANCE_M = 0.04
HIT_TOLERANCE_REL = 0.02
SAMPLE_VOXELS = 200
# Views kept per segment for its colour, best first (one view can be lit or cut badly): those
# that show at least GOOD_VIEW_INSIDE of it inside the image.
GOOD_VIEWS = 3
GOOD_VIEW_INSIDE = 0.75
CLAIM_MARGIN_M = 0.01
MIN_SEEN_VIEWS = 5            # views where most of its visible voxels were hit
MIN_SEEN_SHARE = 0.25          # of the views that could tell
MIN_HIT_RATIO = 0.5           # share of its voxels that are solid (hit more than seen through)
# Things side by side on a table touch at a neck: the top view is eroded NECK_CELLS voxels, and
# each remaining core of at least CORE_CELLS voxels is one thing.
NECK_CELLS = 1
CORE_CELLS = 6
# Things of two colours lying against each other with no neck between them (a red gamepad against a
# white box) meet at a colour edge: the top view's cells fall into two colour groups whose median
# CIELAB chroma (a*, b*: light and shading move lightness far more) lie at least COLOUR_EDGE_DELTA
# apart (red against white: ~45; one object's lit and shaded faces: a few units).
COLOUR_EDGE_DELTA = 25.0
COLOUR_GROUP_ITERATIONS = 10
# Welded along a wall no structure rule found (a short wall seen far away, its normals too noisy to
# vote): a segment at least WELD_MIN_EXTENT_M across (what stands on its own in a room is smaller,
# chairs up to 1.1 m; couches and desks are taken before; what is bigger holds a piece of wall, a
# long front or things standing against them) is cut along its strongest vertical plane when
# that plane holds WELD_PLANE_SHARE of its voxels and spans WELD_PLANE_MIN_SPAN_M along it and in
# height (a wall or a board on it, not one object's side). The plane's voxels lie within
# WELD_PLANE_SLAB_M of it (depth at 3 m scatters a flat board by +-5 cm); planes are tried every
# WELD_ANGLE_STEP_DEG.
WELD_MIN_EXTENT_M = 1.2
WELD_PLANE_SHARE = 0.3
WELD_PLANE_MIN_SPAN_M = 0.6
WELD_PLANE_SLAB_M = 0.06
WELD_ANGLE_STEP_DEG = 3.0


@dataclass
class Segment:
    """A connected group of occupied voxels, gravity frame."""

    voxels: np.ndarray        # M x 3 voxel centres (a, b, h)
    lo: np.ndarray
    hi: np.ndarray
    frames: np.ndarray        # view positions (in cloud.views) that had points in it
    hits: int = 0
    free: int = 0
    seen_views: int = 0
    looked_views: int = 0     # views that saw most of its place unoccluded (hit or through)
    best_view: int = -1       # the view that saw most of it, whole and near
    good_views: tuple[int, ...] = ()   # up to GOOD_VIEWS views that saw most of it, best first
    on_board: bool = False    # cut from a bookcase as standing on one of its boards (`shelves`)

    @property
    def size(self) -> np.ndarray:
        return self.hi - self.lo

    @property
    def hit_ratio(self) -> float:
        """Share of the sampled voxels that are solid."""
        return self.hits / (self.hits + self.free) if self.hits + self.free else 0.0


def object_points(cloud: RoomCloud, structure: Sequence[Element], fronts: bool = False) -> np.ndarray:
    """Mask of the cloud's points that belong to no structure element (and lie below
    MAX_HEIGHT_M; above the floor's slab where the floor was seen); with `fronts`, long vertical
    fronts are cut away too."""
    p = cloud.points
    keep = ((p[:, 2] > FLOOR_SLAB_M) if cloud.floor_seen else np.ones(len(p), bool)) & (p[:, 2] < MAX_HEIGHT_M)
    masks = cloud.__dict__.setdefault("_structure_masks", {})
    for el in structure:
        if el.label == "floor" or (el.label == "front" and not fronts):
            continue
        slab = PLANE_CUT_M if el.label in ("wall", "front") else SURFACE_SLAB_M
        if id(el) not in masks:        # each element's slab is computed once per cloud
            masks[id(el)] = el.contains(p, slab)
        keep &= ~masks[id(el)]
    return keep


def plausible_size(size: np.ndarray) -> bool:
    """Rule "object size": the largest extent between MIN_EXTENT_M and MAX_EXTENT_M."""
    return MIN_EXTENT_M <= float(np.max(size)) <= MAX_EXTENT_M


def voxel_segments(cloud: RoomCloud, mask: np.ndarray, too_big: Optional[list] = None) -> list[Segment]:
    """Connected components (26-neighbourhood) of the voxels that MIN_VOXEL_FRAMES frames saw;
    the point indices of components too big for an object are appended to `too_big`."""
    where = np.flatnonzero(mask)
    p = cloud.points[mask]
    f = cloud.frame[mask]
    if len(p) == 0:
        return []
    origin = p.min(axis=0)
    ijk = np.floor((p - origin) / VOXEL_M).astype(np.int64)
    shape = ijk.max(axis=0) + 1
    flat = (ijk[:, 0] * shape[1] + ijk[:, 1]) * shape[2] + ijk[:, 2]
    nviews = len(cloud.views) + 1
    pairs = np.unique(flat * nviews + f)
    vox, counts = np.unique(pairs // nviews, return_counts=True)
    occupied = vox[counts >= MIN_VOXEL_FRAMES]
    grid = np.zeros(int(np.prod(shape)), bool)
    grid[occupied] = True
    grid = grid.reshape(shape)
    labels, count = ndimage.label(grid, structure=np.ones((3, 3, 3), bool))
    if count == 0:
        return []
    point_label = labels.reshape(-1)[flat]
    # the frames of every component at once, from its (component, frame) pairs
    lf = np.unique(point_label * nviews + f)
    lf = lf[lf >= nviews]
    frames_of = np.split(lf % nviews, np.searchsorted(lf // nviews, np.arange(2, count + 1)))
    objects = ndimage.find_objects(labels)
    out: list[Segment] = []
    sizes = np.bincount(labels.reshape(-1), minlength=count + 1)
    for c in range(1, count + 1):
        if sizes[c] < MIN_VOXELS:
            continue
        sl = objects[c - 1]
        sub = labels[sl] == c
        idx = np.argwhere(sub) + np.array([s.start for s in sl])
        centres = origin + (idx + 0.5) * VOXEL_M
        lo = centres.min(axis=0) - VOXEL_M / 2
        hi = centres.max(axis=0) + VOXEL_M / 2
        if not plausible_size(hi - lo):
            if too_big is not None and float(np.max(hi - lo)) > MAX_EXTENT_M:
                too_big.append(where[point_label == c])
            continue
        out.append(Segment(centres, lo, hi, frames_of[c - 1]))
    return out


# The voxel coordinates a sample's seed is made of are rounded to this (metres): far above the
# last-bit differences another CPU's kernels or thread split leave in them, far below a voxel.
SEED_GRID_M = 1e-4


def voxel_sample(voxels: np.ndarray, n: int = SAMPLE_VOXELS) -> np.ndarray:
    """Up to `n` of a segment's voxels, drawn by a generator seeded from the voxels themselves
    (their coordinates rounded to SEED_GRID_M): the same segment gets the same sample whatever
    else the room holds, and on any machine."""
    if len(voxels) <= n:
        return voxels
    cells = np.rint(np.asarray(voxels, np.float64) / SEED_GRID_M).astype("<i8")
    rng = np.random.default_rng(zlib.crc32(np.ascontiguousarray(cells).tobytes()))
    return voxels[rng.choice(len(voxels), n, replace=False)]


def depth_evidence(seg: Segment, cloud: RoomCloud) -> None:
    """Rule "seen, not seen through": project up to SAMPLE_VOXELS of the segment's voxels into
    every view; where the view's depth lies within the hit tolerance of a voxel it is a hit,
    where it lies beyond, free space (the camera saw through the place). A voxel is solid when
    its hits outnumber its looks through it. Sets hits (solid voxels), free (the others),
    seen_views (views hitting most of the voxels they see), best_view (the view hitting the
    most voxels, the nearer on ties, with all of them inside the image) and good_views (the
    GOOD_VIEWS best views with GOOD_VIEW_INSIDE of them inside the image)."""
    vox = voxel_sample(seg.voxels)
    world = cloud.to_world(vox)
    candidates: list[tuple[int, float, int, bool]] = []   # (hits, -median depth, view, whole)
    hit_v = np.zeros(len(vox), int)
    free_v = np.zeros(len(vox), int)
    seen = looked = 0
    for k, (view, w2c) in enumerate(zip(cloud.views, cloud.world_to_camera)):
        cam = world @ w2c[:3, :3].T + w2c[:3, 3]
        z = cam[:, 2]
        front = z > 0.1
        if not front.any():
            continue
        K = view.K
        zs = np.where(front, z, 1.0)
        u = K[0, 0] * cam[:, 0] / zs + K[0, 2]
        v = K[1, 1] * cam[:, 1] / zs + K[1, 2]
        w, h = view.size
        inside = front & (u >= 0) & (u < w) & (v >= 0) & (v < h)
        if not inside.any():
            continue
        dh, dw = view.depth.shape
        du = np.clip((u[inside] * dw / w).astype(int), 0, dw - 1)
        dv = np.clip((v[inside] * dh / h).astype(int), 0, dh - 1)
        d = view.depth[dv, du].astype(np.float64)
        zi = z[inside]
        tol = HIT_TOLERANCE_M + HIT_TOLERANCE_REL * zi
        known = d > 0
        hit = known & (np.abs(d - zi) <= tol)
        through = known & (d > zi + tol)
        hit_v[inside] += hit
        free_v[inside] += through
        nh = int(hit.sum())
        # a view that could tell: it sees most of the voxels, unoccluded (hit or seen through)
        if int(hit.sum() + through.sum()) >= 0.5 * len(vox):
            looked += 1
        if nh > 0 and nh >= 0.5 * int(known.sum()):
            seen += 1
        if nh > 0 and float(inside.mean()) >= GOOD_VIEW_INSIDE:
            candidates.append((nh, -float(np.median(zi)), k, bool(inside.all())))
    solid = (hit_v >= 1) & (hit_v >= free_v)
    # most hits first, the nearer on ties, the earlier view on full ties
    ranked = sorted(candidates, key=lambda t: (-t[0], -t[1], t[2]))
    seg.good_views = tuple(t[2] for t in ranked[:GOOD_VIEWS])
    seg.hits, seg.free, seg.seen_views = int(solid.sum()), int((~solid).sum()), seen
    seg.best_view = next((t[2] for t in ranked if t[3]), -1)
    seg.looked_views = looked


def exists(seg: Segment) -> bool:
    """The depth existence decision: seen in MIN_SEEN_VIEWS views and MIN_HIT_RATIO of its
    voxels solid."""
    return (seg.seen_views >= max(MIN_SEEN_VIEWS, MIN_SEEN_SHARE * seg.looked_views)
            and seg.hit_ratio >= MIN_HIT_RATIO)


def split_at_necks(seg: Segment) -> list[Segment]:
    """Rule "touching, not joined": erode the segment's top view (its voxels' (a, b) cells) by
    NECK_CELLS; when two or more cores of CORE_CELLS cells remain, every voxel goes to the core
    nearest its cell and each part of MIN_VOXELS is a segment of its own (a gamepad lying
    against a box). Otherwise the segment is returned whole. The parts carry no depth evidence
    yet (`depth_evidence`)."""
    ij = np.floor((seg.voxels[:, :2] - seg.lo[:2]) / VOXEL_M).astype(int)
    top = np.zeros(ij.max(axis=0) + 1, bool)
    top[ij[:, 0], ij[:, 1]] = True
    eight = np.ones((3, 3), bool)
    core = ndimage.binary_erosion(top, structure=eight, iterations=NECK_CELLS)
    labels, n = ndimage.label(core, structure=eight)
    sizes = np.bincount(labels.reshape(-1), minlength=n + 1)
    cores = [c for c in range(1, n + 1) if sizes[c] >= CORE_CELLS]
    if len(cores) < 2:
        return [seg]
    labels = np.where(np.isin(labels, cores), labels, 0)
    return _parts_by_core(seg, labels, ij, cores)


def _parts_by_core(seg: Segment, labels: np.ndarray, ij: np.ndarray, cores: Sequence[int]) -> list[Segment]:
    """Every voxel of `seg` (top-view cell `ij`) goes to the core of `labels` nearest its cell; each
    core's part of MIN_VOXELS is a segment (no depth evidence yet); `seg` whole unless two parts."""
    _, (ni, nj) = ndimage.distance_transform_edt(labels == 0, return_indices=True)
    owner = labels[ni, nj][ij[:, 0], ij[:, 1]]
    parts = []
    for c in cores:
        vox = seg.voxels[owner == c]
        if len(vox) >= MIN_VOXELS:
            parts.append(Segment(vox, vox.min(axis=0) - VOXEL_M / 2, vox.max(axis=0) + VOXEL_M / 2, seg.frames))
    return parts if len(parts) > 1 else [seg]


def split_at_colour_edge(seg: Segment, chroma: np.ndarray) -> list[Segment]:
    """Rule "touching, not one colour": each top-view cell (its voxels' (a, b) cell) takes the
    median CIELAB chroma (a*, b*) of its voxels (`chroma`: N x 2, NaN where no view read the
    voxel); the cells fall into two colour groups (2-means from the two cells farthest apart
    along the chroma's main axis). When the groups' medians lie COLOUR_EDGE_DELTA apart or more
    and each group holds a connected core of CORE_CELLS cells, every voxel goes to the core
    nearest its cell (the largest connected core of each group) and each part of MIN_VOXELS is a
    segment of its own (a red gamepad against a white box: no neck between them). Otherwise the segment is returned whole. The parts carry no
    depth evidence yet (`depth_evidence`)."""
    ij = np.floor((seg.voxels[:, :2] - seg.lo[:2]) / VOXEL_M).astype(int)
    shape = ij.max(axis=0) + 1
    cell = ij[:, 0] * shape[1] + ij[:, 1]
    known = ~np.isnan(chroma).any(axis=1)
    cells = np.unique(cell[known])
    if len(cells) < 2 * CORE_CELLS:
        return [seg]
    order = np.argsort(cell[known], kind="stable")
    sorted_cells, sorted_chroma = cell[known][order], chroma[known][order]
    starts = np.searchsorted(sorted_cells, cells)
    med = np.array([np.median(c, axis=0) for c in np.split(sorted_chroma, starts[1:])])
    axis = med - med.mean(axis=0)
    main = np.linalg.svd(axis, full_matrices=False)[2][0]
    centres = med[[int(np.argmin(axis @ main)), int(np.argmax(axis @ main))]]
    group = np.zeros(len(med), int)
    for _ in range(COLOUR_GROUP_ITERATIONS):
        group = np.argmin(np.linalg.norm(med[:, None, :] - centres[None], axis=2), axis=1)
        if (group == 0).all() or (group == 1).all():
            return [seg]
        centres = np.array([np.median(med[group == g], axis=0) for g in (0, 1)])
    if float(np.linalg.norm(centres[0] - centres[1])) < COLOUR_EDGE_DELTA:
        return [seg]
    eight = np.ones((3, 3), bool)
    labels = np.zeros(shape, int)
    cores: list[int] = []
    for g in (0, 1):
        grid = np.zeros(shape, bool)
        grid[cells[group == g] // shape[1], cells[group == g] % shape[1]] = True
        comp, n = ndimage.label(grid, structure=eight)
        sizes = np.bincount(comp.reshape(-1), minlength=n + 1)
        biggest = int(np.argmax(sizes[1:])) + 1 if n else 0
        if not n or sizes[biggest] < CORE_CELLS:
            return [seg]
        cores.append(g + 1)
        labels[comp == biggest] = g + 1
    return _parts_by_core(seg, labels, ij, cores)


def outside_boxes(points: np.ndarray, boxes: Sequence[tuple[np.ndarray, np.ndarray]],
                  margin: float = CLAIM_MARGIN_M) -> np.ndarray:
    """Mask of the points outside every box (gravity frame, grown by `margin`)."""
    keep = np.ones(len(points), bool)
    for lo, hi in boxes:
        keep &= ~((points >= lo - margin) & (points <= hi + margin)).all(axis=1)
    return keep


def outside_room(seg: Segment, structure: Sequence[Element]) -> bool:
    """Rule "beyond the walls": a segment whose centre lies more than WALL_FAR_M behind a wall
    that surely bounds the room (WALL_SURE_FAR) was seen through a window or a glass partition."""
    centre = ((seg.lo + seg.hi) / 2)[None, :]
    return any(bool(e.behind(centre, WALL_FAR_M)[0]) for e in structure
               if e.label == "wall" and e.far_behind <= WALL_SURE_FAR)


def room_candidates(cloud: RoomCloud, structure: Sequence[Element],
                    claimed: Sequence[tuple[np.ndarray, np.ndarray]] = ()) -> list[Segment]:
    """Every segment of the room inside its walls, with its depth evidence (`depth_evidence`)
    but not yet judged (`exists`). Points inside a `claimed` box (a named object's) are its
    object's and join no segment, so a cup does not weld the magazine beside it into one thing."""
    free = object_points(cloud, structure)
    idx = np.flatnonzero(free)
    free[idx] = outside_boxes(cloud.points[idx], claimed)
    # walls and surfaces apart first; what is still too big for an object (cabinets run into
    # each other along a wall) is cut along the long vertical fronts too
    big: list = []
    segs = voxel_segments(cloud, free, big)
    if big:
        again = np.zeros(len(cloud.points), bool)
        again[np.concatenate(big)] = True
        segs += voxel_segments(cloud, again & free & object_points(cloud, structure, fronts=True))
    segs = [s for s in segs if not outside_room(s, structure)]
    for s in segs:
        depth_evidence(s, cloud)
    return segs


def room_segments(cloud: RoomCloud, structure: Sequence[Element],
                  claimed: Sequence[tuple[np.ndarray, np.ndarray]] = ()) -> list[Segment]:
    """Every segment of the room that passes the depth existence test (`room_candidates`,
    `exists`)."""
    return [s for s in room_candidates(cloud, structure, claimed) if exists(s)]


def strongest_vertical_plane(voxels: np.ndarray) -> tuple[float, float, np.ndarray]:
    """(angle, offset, mask of the voxels within WELD_PLANE_SLAB_M) of the vertical plane holding
    the most voxels: offsets along every horizontal normal direction (WELD_ANGLE_STEP_DEG apart)
    binned 2 * WELD_PLANE_SLAB_M wide, the fullest bin (and its neighbours' centre) wins."""
    best = (0.0, 0.0, np.zeros(len(voxels), bool))
    count = -1
    for deg in np.arange(0.0, 180.0, WELD_ANGLE_STEP_DEG):
        th = np.radians(deg)
        off = voxels[:, 0] * np.cos(th) + voxels[:, 1] * np.sin(th)
        bins = np.floor(off / WELD_PLANE_SLAB_M).astype(int)
        vals, counts = np.unique(bins, return_counts=True)
        # a slab two bins wide: each pair of neighbouring bins
        pair = counts[:-1] + np.where(np.diff(vals) == 1, counts[1:], 0) if len(vals) > 1 else counts
        k = int(np.argmax(pair))
        if int(pair[k]) > count:
            rho = float(np.median(off[(bins == vals[k]) | (bins == vals[min(k + 1, len(vals) - 1)])]))
            count = int(pair[k])
            best = (float(th), rho, np.abs(off - rho) <= WELD_PLANE_SLAB_M)
    return best


def welded_wall(seg: Segment) -> Optional[tuple[float, float, np.ndarray]]:
    """The wall a segment is welded along (`split_at_wall`): (angle, offset, its voxels' mask) of
    its strongest vertical plane when the segment is at least WELD_MIN_EXTENT_M across and the
    plane holds WELD_PLANE_SHARE of its voxels and spans WELD_PLANE_MIN_SPAN_M along it and in
    height; else None."""
    if float(np.max(seg.size)) < WELD_MIN_EXTENT_M:
        return None
    th, rho, on = strongest_vertical_plane(seg.voxels)
    if on.mean() < WELD_PLANE_SHARE:
        return None
    along = -seg.voxels[on, 0] * np.sin(th) + seg.voxels[on, 1] * np.cos(th)
    if float(np.ptp(along)) < WELD_PLANE_MIN_SPAN_M or float(np.ptp(seg.voxels[on, 2])) < WELD_PLANE_MIN_SPAN_M:
        return None
    return th, rho, on


def split_at_wall(seg: Segment, wall: Optional[tuple[float, float, np.ndarray]] = None) -> list[Segment]:
    """Rule "welded along a wall": a segment at least WELD_MIN_EXTENT_M across whose strongest
    vertical plane (`strongest_vertical_plane`) holds WELD_PLANE_SHARE of its voxels and spans
    WELD_PLANE_MIN_SPAN_M along the plane and in height (`welded_wall`; `wall` when already found)
    is cut there: the plane's piece (a piece of wall, or a board on it: its voxels and the parts of
    the rest lying within 2 WELD_PLANE_SLAB_M of the plane, its relief), first, and each other
    connected part of the rest (what stands against it) of MIN_VOXELS are segments of their own,
    without depth evidence yet (`depth_evidence`). Otherwise the segment is returned whole."""
    found = wall if wall is not None else welded_wall(seg)
    if found is None:
        return [seg]
    th, rho, on = found
    off = np.abs(seg.voxels[:, 0] * np.cos(th) + seg.voxels[:, 1] * np.sin(th) - rho)
    rest = np.flatnonzero(~on)
    plane = on.copy()
    parts = []
    if len(rest):
        vox = seg.voxels[rest]
        ijk = np.floor((vox - vox.min(axis=0)) / VOXEL_M + 0.5).astype(int)
        grid = np.zeros(ijk.max(axis=0) + 1, bool)
        grid[tuple(ijk.T)] = True
        labels, n = ndimage.label(grid, structure=np.ones((3, 3, 3), bool))
        owner = labels[tuple(ijk.T)]
        for c in range(1, n + 1):
            idx = rest[owner == c]
            if float(off[idx].max()) <= 2 * WELD_PLANE_SLAB_M:
                plane[idx] = True          # the plane's relief
            elif len(idx) >= MIN_VOXELS:
                parts.append(seg.voxels[idx])
    if not parts or int(plane.sum()) < MIN_VOXELS:
        return [seg]
    return [Segment(v, v.min(axis=0) - VOXEL_M / 2, v.max(axis=0) + VOXEL_M / 2, seg.frames)
            for v in [seg.voxels[plane]] + parts]
