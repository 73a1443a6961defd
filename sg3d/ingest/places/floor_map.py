"""The floor map of a walk: a 2-D grid over the floor, each cell occupied, free or unknown.

Input is what the depth camera saw, in the gravity frame (a, b along the floor, h metres above
it: `sg3d.ingest.discover.room_cloud`), and where the camera was. A cell is
- occupied: enough points between OBSTACLE_LOW and OBSTACLE_HIGH above the floor fell in it
  (furniture, walls, a door leaf: whatever a person would walk into);
- free: the floor was seen in it, or the camera passed over it, and it is not occupied;
- unknown: otherwise (behind walls, under what hid the floor, never looked at).
This is the 2-D occupancy map of a mobile robot's map server (Elfes 1989; here counted, not
probabilistic, because a posed RGB-D walk gives every cell many observations).
"""
from __future__ import annotations

from typing import Any

from dataclasses import dataclass

import numpy as np

UNKNOWN, FREE, OCCUPIED = 0, 1, 2


@dataclass(frozen=True)
class PlacesConfig:
    """Every parameter of the floor map and the room segmentation, with why it has its value."""
    # ~5 cm cells: a 10 cm wall is two cells, a 80 cm door sixteen; finer cells only add noise.
    cell_m: float = 0.05
    # Floor points lie within this of the floor's height (depth noise at 4 m is ~2.5 cm).
    floor_band_m: float = 0.05
    # Obstacles: above floor noise and door sills, below door lintels (2.05 m) and the ceiling.
    obstacle_low_m: float = 0.10
    obstacle_high_m: float = 2.0
    # A cell is occupied with this many obstacle points: flying pixels at depth edges are single.
    obstacle_min_points: int = 3
    # Points beyond this range are too noisy to place a 5 cm cell (Kinect-type depth).
    max_range_m: float = 4.0
    # The camera was carried here, so the floor around it is free: a person stands and turns
    # there, and a camera looking 35 degrees down sees the floor only from ~0.9 m away (0.25 m
    # left a ring of unknown round each look-round that split rooms: recall 0.72 -> 0.86).
    camera_free_m: float = 0.9
    # Unknown cells enclosed by free ones within this radius are free (gaps between floor samples).
    fill_gap_m: float = 0.10
    # Room seeds (`places.rooms`): a maximum of the distance map is a room when it stands this
    # much above the saddle joining it to a wider room (a room is wider than the door into it:
    # a 0.9 m door gives a 0.45 m saddle, a 1.3 m corridor a 0.65 m crest, a 3 m room ~1.2 m).
    min_dynamic_m: float = 0.15
    # ... and the passage is at most this share of the room's width (a 0.8-0.95 m door into a
    # 1.3-1.5 m corridor is 0.55-0.73, an open-plan opening 0.45-0.7 of the rooms it joins; a
    # long room's two halves meet at ~0.8-0.9, a corridor's widenings at its doors at ~0.8).
    passage_ratio: float = 0.75
    # ... and when its widest free circle has at least this radius (a 1.2 m corridor: 0.6 m).
    min_room_radius_m: float = 0.45
    # Filtration step of the distance levels (one cell).
    level_step_m: float = 0.05
    # Two rooms whose border is this share of the narrower one's width are one. Measured on 10
    # generated apartments: borders between two true rooms (doors, openings) were 0.02-0.69 of
    # the narrower room's width, borders cutting one true room (a corridor's stretches, a long
    # room's ends) 0.72-0.87 where they were wide at all.
    wide_passage_ratio: float = 0.7
    # Obstacle cells this wide inside one border do not split it into two passages (a corridor's
    # border cut by 1-4 noise cells measured 0.86 + 0.21 m and stayed two rooms).
    passage_gap_m: float = 0.15
    # A room has at least this much free floor; smaller pieces join their widest neighbour.
    min_room_area_m2: float = 1.5
    # A border narrower than this between two rooms is no doorway: a single cell is two rooms
    # touching at a corner through a gap in a wall seen edge-on (0.15 m lost 1 of 51 doorways on
    # 12 apartments: a half-open door's border can be 2-3 cells where the leaf hides the floor).
    min_doorway_m: float = 0.1
    # Occupied cells (furniture, walls) belong to the nearest room within this distance.
    furniture_reach_m: float = 1.0


@dataclass
class FloorMap:
    """The map: `state[i, j]` for the cell whose centre is origin + (i + 0.5, j + 0.5) * cell."""
    state: np.ndarray          # int8 UNKNOWN / FREE / OCCUPIED, shape (na, nb)
    origin: np.ndarray         # (a, b) of the grid's corner
    cell: float

    def cells_of(self, ab: np.ndarray) -> np.ndarray:
        """Integer cell indices of (a, b) points (may lie outside the grid)."""
        return np.floor((np.asarray(ab, float)[..., :2] - self.origin) / self.cell).astype(np.int64)

    def centres(self, ij: np.ndarray) -> np.ndarray:
        return self.origin + (np.asarray(ij, float) + 0.5) * self.cell

    def inside(self, ij: np.ndarray) -> np.ndarray:
        return (ij[..., 0] >= 0) & (ij[..., 1] >= 0) & (ij[..., 0] < self.state.shape[0]) & \
            (ij[..., 1] < self.state.shape[1])


def grid_around(points: np.ndarray, cameras: np.ndarray, cell: float,
                margin: float = 0.5) -> tuple[np.ndarray, tuple[int, ...]]:
    """The grid's corner and shape covering every point and camera with `margin` m to spare."""
    ab = np.concatenate([points[:, :2], cameras[:, :2]]) if len(cameras) else points[:, :2]
    lo = np.floor((ab.min(axis=0) - margin) / cell) * cell
    hi = ab.max(axis=0) + margin
    return lo, tuple(int(v) for v in np.ceil((hi - lo) / cell))


def count_in_cells(shape: tuple, ij: np.ndarray) -> np.ndarray:
    """How many of the cell indices `ij` (N x 2) fall in each cell of a grid of `shape`."""
    ok = (ij[:, 0] >= 0) & (ij[:, 1] >= 0) & (ij[:, 0] < shape[0]) & (ij[:, 1] < shape[1])
    flat = np.ravel_multi_index((ij[ok, 0], ij[ok, 1]), shape)
    return np.bincount(flat, minlength=shape[0] * shape[1]).reshape(shape)


def obstacle_cells(counts: np.ndarray, cfg: PlacesConfig) -> np.ndarray:
    """Rule "occupied": at least `obstacle_min_points` points between `obstacle_low_m` and
    `obstacle_high_m` above the floor fell in the cell."""
    return counts >= cfg.obstacle_min_points


def camera_cells(fm_shape: tuple, centres_ij: np.ndarray, cell: float, cfg: PlacesConfig) -> np.ndarray:
    """Rule "the camera passed here": cells within `camera_free_m` of a camera's foot point."""
    from scipy import ndimage

    mark = np.zeros(fm_shape, bool)
    ok = (centres_ij[:, 0] >= 0) & (centres_ij[:, 1] >= 0) & (centres_ij[:, 0] < fm_shape[0]) & \
        (centres_ij[:, 1] < fm_shape[1])
    mark[centres_ij[ok, 0], centres_ij[ok, 1]] = True
    if not mark.any():                 # no camera on the grid: nothing was walked
        return mark
    return ndimage.distance_transform_edt(~mark) * cell <= cfg.camera_free_m


def fill_gaps(free: np.ndarray, blocked: np.ndarray, cell: float, cfg: PlacesConfig) -> np.ndarray:
    """Rule "gaps between floor samples": a morphological closing of the free cells with a disc of
    `fill_gap_m`, never over a `blocked` (occupied) cell."""
    from scipy import ndimage

    r = max(1, int(round(cfg.fill_gap_m / cell)))
    yy, xx = np.mgrid[-r:r + 1, -r:r + 1]
    disc = xx ** 2 + yy ** 2 <= r * r
    closed = ndimage.binary_closing(free, structure=disc, border_value=0)
    return (closed | free) & ~blocked


def floor_map(points: np.ndarray, cameras: np.ndarray, cfg: PlacesConfig = PlacesConfig()) -> FloorMap:
    """The floor map (module docstring) of gravity-frame `points` (N x 3: a, b, h above the floor;
    already limited to `max_range_m` from their camera) and camera positions (M x 3, same frame)."""
    cameras = np.asarray(cameras, float).reshape(-1, 3)
    origin, shape = grid_around(points, cameras, cfg.cell_m)
    fm = FloorMap(np.zeros(shape, np.int8), origin, cfg.cell_m)
    h = points[:, 2]
    ij = fm.cells_of(points)
    floor = count_in_cells(shape, ij[np.abs(h) <= cfg.floor_band_m]) > 0
    band = (h >= cfg.obstacle_low_m) & (h <= cfg.obstacle_high_m)
    counts = count_in_cells(shape, ij[band])
    occupied = obstacle_cells(counts, cfg)
    free = (floor | camera_cells(shape, fm.cells_of(cameras), cfg.cell_m, cfg)) & ~occupied
    free = fill_gaps(free, occupied, cfg.cell_m, cfg)
    fm.state[free] = FREE
    fm.state[occupied] = OCCUPIED
    return fm


def walk_points(frames: Any, basis: np.ndarray, floor: float, stride: int = 4,
                max_range: float = PlacesConfig.max_range_m) -> tuple[np.ndarray, np.ndarray]:
    """Gravity-frame points of every `stride`-th pixel of each frame's depth within `max_range`
    (h above the floor at `floor` = p . up), and the cameras' positions in the same frame."""
    pts, cams = [], []
    for f in frames:
        d = f.depth[::stride, ::stride].astype(np.float64)
        v, u = np.mgrid[0:f.depth.shape[0]:stride, 0:f.depth.shape[1]:stride]
        ok = (d > 0) & (d < max_range)
        z = d[ok]
        cam = np.stack([(u[ok] - f.K[0, 2]) / f.K[0, 0] * z, (v[ok] - f.K[1, 2]) / f.K[1, 1] * z, z], axis=1)
        world = cam @ f.pose[:3, :3].T + f.pose[:3, 3]
        local = world @ basis.T
        local[:, 2] -= floor
        pts.append(local)
        c = f.pose[:3, 3] @ basis.T
        cams.append([c[0], c[1], c[2] - floor])
    return (np.concatenate(pts) if pts else np.zeros((0, 3))), np.asarray(cams, float).reshape(-1, 3)
