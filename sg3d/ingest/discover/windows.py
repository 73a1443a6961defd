"""Windows from physics: a window is a hole in a wall that the views saw through.

Each wall (`sg3d.ingest.discover.structure`, a vertical plane (theta, rho) in the gravity frame)
gets a grid on its face, FACE_CELL_M cells along the wall x height. Every view's small depth grid
(`room_cloud.camera_grid`) is cast onto the plane: each pixel's ray meets the face in a cell, and
its depth says what the view saw there (`ray_verdict`): the wall (a return on the plane), through
it (no return, or one beyond the plane), or something in front of it (a return before the plane:
unknown, never a hole). A cell is open when the views saw through it (`open_cell`); open cells
joined into a rectangle are a window when the rectangle is big enough (`window_sized`), its bottom
is well above the floor (`above_floor`: a door reaches the floor) and the wall's own face bounds it
on both sides and below (`in_the_wall`).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
from scipy import ndimage

from sg3d.ingest.discover.room_cloud import MAX_RANGE_M, RoomCloud, camera_grid
from sg3d.ingest.discover.structure import (
    WALL_ANGLE_BIN_DEG,
    WALL_MIN_LENGTH,
    WALL_NORMAL_COS,
    WALL_OFFSET_BIN_M,
    WALL_SLAB_M,
    WALL_SAME_DEG,
    WALL_SAME_M,
    Element,
    _angle_gap_deg,
    fitted_plane,
    plane_votes,
)

FACE_CELL_M = 0.05
# A return within PLANE_SLAB_M of the plane (depth noise, the reveal of a hole inside the wall's
# thickness) is the wall; before it by more, something stood in front. What a window shows is
# outside: no return, or one metres away; a return less than THROUGH_M beyond the plane is a
# recess (a bookcase's back, a niche), not a hole through the wall.
PLANE_SLAB_M = 0.10
THROUGH_M = 0.5
# A ray meeting the face at a slant steeper than this (|cos| to the plane's normal below it)
# lands in a cell by luck of noise: not counted.
MIN_INCIDENCE_COS = 0.3
MIN_THROUGH_VIEWS = 2          # a cell is open when at least this many views saw through it ...
# ... and more views saw through it than saw the wall there (a stray dropout on a wall is outvoted).
MIN_WINDOW_M = 0.4             # a window is at least this wide and this tall
# A door's hole reaches the floor (its bottom within a cell or two of 0); the lowest windows'
# sills are about knee height. A hole starting lower than this is a doorway, a glass door, or
# the space under furniture, never a window.
MIN_SILL_M = 0.3
# The wall's own face must bound the hole: the two cells beside each side (and under its bottom)
# hold a wall cell along at least this share of the side.
BOUND_SHARE = 0.5
BOUND_CELLS = 2
# Open strips narrower than OPENING_CELLS (0.25 m, well under a window's least size) are taken
# off before joining (depth dropouts along a silhouette line up in streaks), and of the
# rectangle's cells that some view decided at least MIN_FILL are open (a window is a rectangle:
# an L of open cells round a wall corner is not).
OPENING_CELLS = 5
MIN_FILL = 0.7

# A window's wall: a vertical plane of the Hough vote (`structure.plane_votes`, at least
# PLANE_MIN_VOTES points, at most MAX_PLANES of them) whose points run WALL_MIN_LENGTH along it
# and reach WINDOW_WALL_MIN_TOP_M high (a sill and a window's lower half: furniture fronts end lower).
PLANE_MIN_VOTES = 300
MAX_PLANES = 16
# A strong wall's noisy normals spread its votes over many bins: the peaks beside it are tried
# (and found to be the same wall) before the next wall's; this many peaks are tried in all.
MAX_PEAKS = 80
WINDOW_WALL_MIN_TOP_M = 1.0

THROUGH, WALL, UNKNOWN = 0, 1, 2


@dataclass
class Face:
    """The votes on one wall's face: per cell (along, height) the views that saw through it,
    saw the wall, saw something in front of it or a recess (UNKNOWN)."""

    wall: Element
    along0: float
    votes: np.ndarray          # 3 x n_along x n_height (THROUGH, WALL, FRONT)


def ray_verdict(depth: np.ndarray, plane_depth: np.ndarray) -> np.ndarray:
    """Rule "what a ray saw at the plane" (depths along the camera's axis): WALL within
    PLANE_SLAB_M of the plane; THROUGH where there was no return (depth 0) or the return lies
    more than THROUGH_M beyond it; UNKNOWN otherwise (something in front, or a recess)."""
    out = np.full(depth.shape, UNKNOWN, np.int64)
    out[np.abs(depth - plane_depth) <= PLANE_SLAB_M] = WALL
    out[(depth <= 0) | (depth > plane_depth + THROUGH_M)] = THROUGH
    return out


def open_cell(through: np.ndarray, wall: np.ndarray) -> np.ndarray:
    """Rule "a cell is open": at least MIN_THROUGH_VIEWS views saw through it and more views saw
    through it than saw the wall (views that saw something in front say nothing)."""
    return (through >= MIN_THROUGH_VIEWS) & (through > wall)


def window_sized(width: float, height: float) -> bool:
    """Rule "a window's size": at least MIN_WINDOW_M wide and MIN_WINDOW_M tall."""
    return width >= MIN_WINDOW_M and height >= MIN_WINDOW_M


def above_floor(bottom: float) -> bool:
    """Rule "a window is not a door": its bottom lies at least MIN_SILL_M above the floor."""
    return bottom >= MIN_SILL_M


def in_the_wall(solid: np.ndarray, rows: slice, cols: slice) -> bool:
    """Rule "a window is in the wall": within BOUND_CELLS cells beside its left side, beside its
    right side and under its bottom, the wall's own face was seen along at least BOUND_SHARE of
    each (`solid`: along x height cells where the views saw the wall)."""
    a0, a1, h0, h1 = cols.start, cols.stop, rows.start, rows.stop
    n_a, n_h = solid.shape
    if a0 < 1 or a1 >= n_a or h0 < 1:
        return False
    left = solid[max(0, a0 - BOUND_CELLS):a0, h0:h1].any(axis=0)
    right = solid[a1:a1 + BOUND_CELLS, h0:h1].any(axis=0)
    below = solid[a0:a1, max(0, h0 - BOUND_CELLS):h0].any(axis=1)
    return all(float(np.mean(side)) >= BOUND_SHARE for side in (left, right, below))


def _axes(wall: Element) -> tuple[np.ndarray, np.ndarray, float]:
    assert wall.plane is not None
    theta, rho = wall.plane
    n = np.array([np.cos(theta), np.sin(theta)])
    return n, np.array([-n[1], n[0]]), rho


@dataclass
class Rays:
    """A view's small depth grid as rays in the gravity frame: the camera's centre (h above the
    floor), each pixel's direction scaled to depth 1 along the camera's axis, and its depth."""

    centre: np.ndarray
    direction: np.ndarray      # N x 3
    length: np.ndarray         # N: |direction|
    depth: np.ndarray          # H x W, metres, 0 = no return


def view_rays(cloud: RoomCloud) -> list[Rays]:
    out = []
    for view in cloud.views:
        d = view.depth.astype(np.float64)
        g = camera_grid(replace(view, depth=np.ones_like(d)))[0].reshape(-1, 3) @ (cloud.basis @ view.pose[:3, :3]).T
        centre = cloud.basis @ view.pose[:3, 3]
        centre[2] -= cloud.floor
        out.append(Rays(centre, g, np.linalg.norm(g, axis=1), d))
    return out


def face_votes(rays: list[Rays], wall: Element) -> Optional[Face]:
    """Every view's verdict (`view_verdicts`) per cell of the wall's face: one vote per view and
    cell, its pixels' most common verdict there."""
    _n, t, _rho = _axes(wall)
    ends = np.array([wall.lo[:2] @ t, wall.hi[:2] @ t])
    along0, along1 = float(ends.min()) - 0.5, float(ends.max()) + 0.5
    shape = (int(np.ceil((along1 - along0) / FACE_CELL_M)), int(np.ceil((float(wall.hi[2]) + 0.2) / FACE_CELL_M)))
    if min(shape) <= 0:
        return None
    cells = shape[0] * shape[1]
    votes = np.zeros((3, cells), np.int32)
    for r in rays:
        hit = view_verdicts(r, wall)
        if hit is None:
            continue
        where, verdict = hit
        a = np.floor((where[:, :2] @ t - along0) / FACE_CELL_M).astype(int)
        h = np.floor(where[:, 2] / FACE_CELL_M).astype(int)
        inside = (a >= 0) & (a < shape[0]) & (h >= 0) & (h < shape[1])
        per = np.bincount(verdict[inside] * cells + a[inside] * shape[1] + h[inside], minlength=3 * cells)
        per = per.reshape(3, cells)
        seen = np.flatnonzero(per.sum(axis=0) > 0)
        votes[np.argmax(per[:, seen], axis=0), seen] += 1
    return Face(wall, along0, votes.reshape((3,) + shape))


def view_verdicts(r: Rays, wall: Element) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """Where a view's rays meet the wall's plane (gravity-frame points) and what each saw there
    (`ray_verdict`), for a view on the room's side of the wall, rays that meet it within
    MAX_RANGE_M and not at a slant (MIN_INCIDENCE_COS). A no-return counts as seen through only
    inside an area of no return (`hole_pixels`): a depth sensor drops pixels along silhouettes."""
    n, _t, rho = _axes(wall)
    off = float(r.centre[:2] @ n) - rho
    if wall.side * off <= 0:
        return None
    toward = r.direction[:, :2] @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        zp = -off / toward
    ok = (zp > 0.2) & (zp * r.length < MAX_RANGE_M) & (np.abs(toward) >= MIN_INCIDENCE_COS * r.length)
    if not ok.any():
        return None
    verdict = ray_verdict(r.depth.reshape(-1), np.where(ok, zp, 0.0))
    through = hole_pixels((verdict == THROUGH).reshape(r.depth.shape)).reshape(-1)
    verdict[(verdict == THROUGH) & ~through] = UNKNOWN
    return r.centre + zp[ok, None] * r.direction[ok], verdict[ok]


def hole_pixels(through: np.ndarray) -> np.ndarray:
    """Rule "a hole is an area": the seen-through pixels whose 8 neighbours were seen through
    too (a 3 x 3 erosion; the image's border counts as seen through)."""
    return ndimage.binary_erosion(through, np.ones((3, 3), bool), border_value=1)


def rectangle_fill(opened: np.ndarray, wall: np.ndarray) -> float:
    """The share of a rectangle's decided cells (open, or seen as wall) that are open."""
    decided = int(np.count_nonzero(opened | wall))
    return int(np.count_nonzero(opened)) / decided if decided else 0.0


def face_windows(face: Face) -> list[Element]:
    """The windows in one face: open cells (`open_cell`) with gaps of a cell closed and strips
    narrower than OPENING_CELLS taken off (a window is an area, not a streak along an edge),
    joined; each rectangle kept by `window_sized`, `above_floor`, `in_the_wall` and
    `rectangle_fill` (at least MIN_FILL) is an Element "window" (its box on the plane; n_points
    and frames: the most views that saw through one of its cells)."""
    through, wall = face.votes[THROUGH], face.votes[WALL]
    opened = ndimage.binary_closing(open_cell(through, wall), iterations=1)
    opened = ndimage.binary_opening(opened, np.ones((OPENING_CELLS, OPENING_CELLS), bool))
    solid = (wall > through) & ~opened
    labels, _ = ndimage.label(opened)
    n, t, rho = _axes(face.wall)
    out = []
    for k, box in enumerate(ndimage.find_objects(labels), start=1):
        if box is None:
            continue
        cols, rows = box
        width = (cols.stop - cols.start) * FACE_CELL_M
        bottom, top = rows.start * FACE_CELL_M, rows.stop * FACE_CELL_M
        if not (window_sized(width, top - bottom) and above_floor(bottom) and in_the_wall(solid, rows, cols)
                and rectangle_fill(labels[box] == k, solid[box]) >= MIN_FILL):
            continue
        a0 = face.along0 + cols.start * FACE_CELL_M
        ends = np.array([rho * n + a0 * t, rho * n + (a0 + width) * t])
        lo = np.r_[ends.min(axis=0), bottom]
        hi = np.r_[ends.max(axis=0), top]
        views = int(through[box][labels[box] == k].max())
        out.append(Element("window", lo, hi, views, views, plane=face.wall.plane, side=face.wall.side))
    return out


def wall_planes(cloud: RoomCloud) -> list[Element]:
    """Rule "a window's wall": the strongest vertical planes of the Hough vote (at least
    PLANE_MIN_VOTES, MAX_PLANES of them from at most MAX_PEAKS peaks, each peak's neighbourhood
    cleared), each fitted to its
    points (`structure.fitted_plane`) and none the same as one before (WALL_SAME_DEG,
    WALL_SAME_M), whose points within
    WALL_SLAB_M run WALL_MIN_LENGTH along the plane and reach WINDOW_WALL_MIN_TOP_M high. Not only
    the walls that bound the room: a walk's cloud holds many rooms, each wall with rooms behind it."""
    p, n = cloud.points, cloud.normals
    vert = (np.abs(n[:, 2]) < WALL_NORMAL_COS) & (np.linalg.norm(n[:, :2], axis=1) > 0.5)
    q = p[vert]
    if len(q) < PLANE_MIN_VOTES:
        return []
    acc, rmin = plane_votes(q, n[vert])
    cams = np.array([v.pose[:3, 3] @ cloud.basis.T for v in cloud.views])
    out: list[Element] = []
    for _ in range(MAX_PEAKS):
        if len(out) >= MAX_PLANES:
            break
        t, r = np.unravel_index(int(np.argmax(acc)), acc.shape)
        if acc[t, r] < PLANE_MIN_VOTES:
            break
        acc[max(0, t - 3):t + 4, max(0, r - 3):r + 4] = 0
        th = (t + 0.5) * np.radians(WALL_ANGLE_BIN_DEG)
        off = q[:, 0] * np.cos(th) + q[:, 1] * np.sin(th) - (rmin + (r + 0.5) * WALL_OFFSET_BIN_M)
        near = np.abs(off) <= WALL_SLAB_M
        if np.count_nonzero(near) < PLANE_MIN_VOTES:
            continue
        # the vote's 2-degree bins leave a long wall's ends a hand's width off its plane
        th, rh = fitted_plane(q[:, :2], th, rmin + (r + 0.5) * WALL_OFFSET_BIN_M + float(np.median(off[near])))
        near = np.abs(q[:, 0] * np.cos(th) + q[:, 1] * np.sin(th) - rh) <= WALL_SLAB_M
        pts = q[near]
        along = -pts[:, 0] * np.sin(th) + pts[:, 1] * np.cos(th)
        if np.ptp(along) < WALL_MIN_LENGTH or np.percentile(pts[:, 2], 99) < WINDOW_WALL_MIN_TOP_M:
            continue
        if any(_angle_gap_deg(th, e.plane[0]) <= WALL_SAME_DEG and abs(np.cos(th - e.plane[0]) * rh - e.plane[1])
               <= WALL_SAME_M for e in out if e.plane is not None):
            continue
        side = float(np.sign(np.median(cams[:, 0] * np.cos(th) + cams[:, 1] * np.sin(th)) - rh)) or 1.0
        out.append(Element("wall", pts.min(axis=0), pts.max(axis=0), len(pts), 0, plane=(float(th), rh), side=side))
    return out


def windows(cloud: RoomCloud) -> list[Element]:
    """The windows in every wall the walk saw (`wall_planes`, `face_votes`, `face_windows`)."""
    out: list[Element] = []
    rays = view_rays(cloud)
    for wall in wall_planes(cloud):
        face = face_votes(rays, wall)
        if face is not None:
            out += face_windows(face)
    return out
