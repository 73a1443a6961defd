"""Rooms and doorways from the floor map (`places.floor_map`).

Method: marker-controlled watershed of the free space's distance transform (Beucher and Meyer
1993), the markers chosen by their dynamic (Grimaud 1992) in a filtration of the distance map.
It is the distance-transform room segmentation of Bormann et al. ("Room segmentation: survey,
implementation, and analysis", ICRA 2016) and Hydra's room detection (Hughes et al., RSS 2022:
components of the free-space places that survive a dilation of the obstacles), with one change
both papers discuss as their weakness: they cut at ONE distance, which keeps a corridor
(narrow) or splits rooms joined by a wide opening (wide), not both. Here every distance level
is visited from the widest down, and a maximum is a room when it rises `min_dynamic_m` above the
saddle where it meets a wider one: the room is noticeably wider than the passage into it.
Doorways are the narrow passages where two rooms' cells meet.
"""
from __future__ import annotations

import heapq
from dataclasses import dataclass, field

import numpy as np

from sg3d.ingest.places.floor_map import FREE, OCCUPIED, UNKNOWN, FloorMap, PlacesConfig

N4 = ((1, 0), (-1, 0), (0, 1), (0, -1))


@dataclass
class Place:
    """One room found: its label in `Places.labels`, footprint polygon (a, b, metres) and area."""
    label: int
    polygon: list[list[float]]
    area_m2: float
    free_m2: float
    centre: list[float]
    unseen_outline: float = 0.0       # share of its outline no seen wall closes (`unseen_outline`)


@dataclass
class Passage:
    """A doorway: where the free cells of rooms a and b meet; its middle and clear width."""
    a: int
    b: int
    position: list[float]
    width_m: float


@dataclass
class Places:
    rooms: list[Place] = field(default_factory=list)
    doorways: list[Passage] = field(default_factory=list)
    labels: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), np.int32))   # 0: no room
    floor: FloorMap | None = None


def distance_map(free: np.ndarray, cell: float) -> np.ndarray:
    """Each free cell's distance (m) to the nearest cell that is not free (Euclidean transform)."""
    from scipy import ndimage

    return ndimage.distance_transform_edt(free) * cell


def own_room(peak: float, saddle: float, cfg: PlacesConfig) -> bool:
    """Rule "a room is wider than the passage into it": a free space whose widest circle has
    radius `peak`, joined to a wider one through a passage of half-width `saddle`, is a room of
    its own when the passage is narrower than the room by `min_dynamic_m` (its dynamic) and by
    the share `passage_ratio` (saddle <= ratio * peak)."""
    return peak - saddle >= cfg.min_dynamic_m and saddle <= cfg.passage_ratio * peak


def room_seeds(dist: np.ndarray, cfg: PlacesConfig) -> np.ndarray:
    """The filtration of {dist >= t} from the largest t down to `min_room_radius_m`: a component
    born at peak p that meets an older (wider) one at level t stays a room when `own_room(p, t)`,
    else it joins the older one. Returns the seed labels (0: no seed) at the lowest level."""
    from scipy import ndimage

    seeds = np.zeros(dist.shape, np.int32)
    peak: dict[int, float] = {}
    top = float(dist.max()) if dist.size else 0.0
    for t in np.arange(top, cfg.min_room_radius_m - 1e-9, -cfg.level_step_m):
        comp, n = ndimage.label(dist >= t)
        for c, sl in enumerate(ndimage.find_objects(comp), start=1):
            inside = comp[sl] == c
            here = seeds[sl]
            ids = [int(k) for k in np.unique(here[inside]) if k]
            if not ids:
                k = len(peak) + 1
                peak[k] = float(dist[sl][inside].max())
                here[inside] = k
                continue
            ids.sort(key=lambda k: -peak[k])
            for k in ids[1:]:
                if not own_room(peak[k], t, cfg):
                    here[here == k] = ids[0]
            if len(ids) == 1:
                here[inside & (here == 0)] = ids[0]
    return seeds


def flood(free: np.ndarray, dist: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """Meyer's flooding: every free cell joins the seed it is reached from first when the cells
    are visited from the widest (largest distance) down, through free 4-neighbours."""
    labels = seeds.copy()
    heap = [(-float(dist[i, j]), int(i), int(j)) for i, j in zip(*np.nonzero(seeds))]
    heapq.heapify(heap)
    na, nb = free.shape
    while heap:
        _, i, j = heapq.heappop(heap)
        for di, dj in N4:
            a, b = i + di, j + dj
            if 0 <= a < na and 0 <= b < nb and free[a, b] and not labels[a, b]:
                labels[a, b] = labels[i, j]
                heapq.heappush(heap, (-float(dist[a, b]), a, b))
    return labels


def contacts(labels: np.ndarray) -> dict[tuple[int, int], list[tuple[int, int]]]:
    """Pairs of labels whose cells touch (4-neighbours), with the cells on the lower label's side."""
    out: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for axis in (0, 1):
        a = labels[:-1, :] if axis == 0 else labels[:, :-1]
        b = labels[1:, :] if axis == 0 else labels[:, 1:]
        for i, j in zip(*np.nonzero((a > 0) & (b > 0) & (a != b))):
            p, q = int(a[i, j]), int(b[i, j])
            key = (min(p, q), max(p, q))
            out.setdefault(key, []).append((int(i), int(j)))
    return out


def borders(labels: np.ndarray, gap_cells: int = 1) -> list[tuple[int, int, np.ndarray]]:
    """Each separate border between two touching rooms (a, b, its cells): the cells of one pair
    split into groups whose cells lie within `gap_cells` of each other, so two doors between the
    same rooms are two borders while a few obstacle cells inside one passage (a flying pixel, a
    chair leg) do not split it."""
    from scipy import ndimage

    out = []
    r = (gap_cells + 1) // 2         # both sides grown by r bridge a gap of 2r >= gap_cells cells
    reach = np.ones((2 * r + 1, 2 * r + 1), bool)
    for (a, b), cells in sorted(contacts(labels).items()):
        ij = np.asarray(cells)
        mark = np.zeros(labels.shape, bool)
        mark[ij[:, 0], ij[:, 1]] = True
        groups, n = ndimage.label(ndimage.binary_dilation(mark, structure=reach) if r else mark,
                                  structure=np.ones((3, 3), bool))
        g = groups[ij[:, 0], ij[:, 1]]
        out += [(a, b, np.unique(ij[g == k], axis=0)) for k in range(1, n + 1)]
    return out


def merge_small(labels: np.ndarray, cell: float, cfg: PlacesConfig) -> np.ndarray:
    """Rule "a room has floor to stand on": a room of less than `min_room_area_m2` free floor
    joins the neighbour it shares the longest border with (or is dropped without one)."""
    while True:
        ids, counts = np.unique(labels[labels > 0], return_counts=True)
        small = [(c, k) for k, c in zip(ids, counts) if c * cell * cell < cfg.min_room_area_m2]
        if not small:
            return labels
        _, k = min(small)
        touching = {pair: len(cells) for pair, cells in contacts(labels).items() if k in pair}
        if touching:
            pair = max(touching, key=lambda p: touching[p])
            labels[labels == k] = pair[0] if pair[1] == k else pair[1]
        else:
            labels[labels == k] = 0


def merge_wide(labels: np.ndarray, dist: np.ndarray, cell: float, cfg: PlacesConfig) -> np.ndarray:
    """Rule "a doorway is narrower than both rooms": two touching rooms with a border at least
    `wide_passage_ratio` of the narrower one's widest free circle (its diameter) are one room
    (a corridor's stretches between doors, a long room's two ends); the widest first."""
    while True:
        peak = {int(k): float(dist[labels == k].max()) for k in np.unique(labels[labels > 0])}
        wide = []
        for a, b, cells in borders(labels, max(1, int(round(cfg.passage_gap_m / cell)))):
            ratio = passage_width(cells * cell, cell) / (2 * min(peak[a], peak[b]))
            if ratio >= cfg.wide_passage_ratio:
                wide.append((ratio, a, b))
        if not wide:
            return labels
        _, a, b = max(wide)
        labels[labels == b] = a


def renumber(labels: np.ndarray) -> np.ndarray:
    """Labels 1..n in the order of their first cell (row-major): stable for the same map."""
    out = np.zeros_like(labels)
    order = []
    for k in labels.ravel():
        if k and k not in order:
            order.append(int(k))
    for n, k in enumerate(order, start=1):
        out[labels == k] = n
    return out


def passage_width(cells: np.ndarray, cell: float) -> float:
    """The clear width of a doorway: the extent of its border cells along their main direction."""
    if len(cells) < 2:
        return cell
    c = cells - cells.mean(axis=0)
    _, _, vt = np.linalg.svd(c, full_matrices=False)
    s = c @ vt[0]
    return float(s.max() - s.min() + cell)


def doorways(labels: np.ndarray, fm: FloorMap, cfg: PlacesConfig = PlacesConfig()) -> list[Passage]:
    """Rule "a doorway is where two rooms meet": each separate border between two rooms
    (`borders`) at least `min_doorway_m` wide is one passage at the middle of its cells, as wide
    as it (`passage_width`)."""
    out = []
    for a, b, cells in borders(labels, max(1, int(round(cfg.passage_gap_m / fm.cell)))):
        xy = fm.centres(cells)
        width = passage_width(xy, fm.cell)
        if width >= cfg.min_doorway_m:
            out.append(Passage(a, b, [round(float(v), 4) for v in xy.mean(axis=0)], round(width, 3)))
    return out


def room_extent(labels: np.ndarray, occupied: np.ndarray, cell: float, cfg: PlacesConfig) -> np.ndarray:
    """Rule "furniture is in the room it stands in": every occupied cell within
    `furniture_reach_m` of a room's free cells takes the nearest one's label."""
    from scipy import ndimage

    dist, (ii, jj) = ndimage.distance_transform_edt(labels == 0, return_indices=True)
    near = labels[ii, jj]
    out = labels.copy()
    grow = occupied & (labels == 0) & (dist * cell <= cfg.furniture_reach_m)
    out[grow] = near[grow]
    return out


def unseen_outline(extent: np.ndarray, state: np.ndarray, k: int) -> float:
    """Rule "a room's outline was never seen": of room k's outline cells (its cells with a
    4-neighbour outside it), the share that are free floor with a never-seen (UNKNOWN) cell
    beside them, i.e. where no wall was seen closing the room. A wall seen is occupied cells on
    the outline; a doorway leads into another room's cells, which are seen."""
    from scipy import ndimage

    mine = extent == k
    outline = mine & ~ndimage.binary_erosion(mine, border_value=0)
    if not outline.any():
        return 0.0
    unknown = np.pad(state == UNKNOWN, 1, constant_values=True)
    beside = np.zeros_like(mine)
    for di, dj in N4:
        beside |= unknown[1 + di:unknown.shape[0] - 1 + di, 1 + dj:unknown.shape[1] - 1 + dj]
    open_ = outline & (state == FREE) & beside
    return round(float(open_.sum()) / float(outline.sum()), 3)


def footprint(mask: np.ndarray, fm: FloorMap) -> list[list[float]]:
    """The outline of one room's cells as a polygon of (a, b) metres (OpenCV contour, simplified
    to one cell)."""
    import cv2

    contours, _ = cv2.findContours(mask.astype(np.uint8).T.copy(), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    if not contours:
        return []
    c = max(contours, key=cv2.contourArea)
    c = cv2.approxPolyDP(c, 1.0, True).reshape(-1, 2)
    ab = fm.origin + (c + 0.5) * fm.cell          # a contour point of mask.T is (x, y) = (i, j)
    return [[round(float(a), 3), round(float(b), 3)] for a, b in ab]


def segment_rooms(fm: FloorMap, cfg: PlacesConfig = PlacesConfig()) -> Places:
    """Rooms and doorways of a floor map (module docstring)."""
    free = fm.state == FREE
    dist = distance_map(free, fm.cell)
    labels = flood(free, dist, room_seeds(dist, cfg))
    labels = renumber(merge_wide(merge_small(labels, fm.cell, cfg), dist, fm.cell, cfg))
    extent = room_extent(labels, fm.state == OCCUPIED, fm.cell, cfg)
    rooms = []
    for k in range(1, int(labels.max()) + 1):
        mask = extent == k
        centre = fm.centres(np.argwhere(labels == k)).mean(axis=0)
        rooms.append(Place(k, footprint(mask, fm), round(float(mask.sum()) * fm.cell ** 2, 3),
                           round(float((labels == k).sum()) * fm.cell ** 2, 3), [round(float(v), 3) for v in centre],
                           unseen_outline(extent, fm.state, k)))
    return Places(rooms, doorways(labels, fm, cfg), extent, fm)


# Rule "a room's structure" (`rooms_bounded`): a floor or wall bounds the found rooms whose cells
# lie within STRUCTURE_REACH_M of its footprint (a wall's half thickness and the band of furniture
# against it) along at least STRUCTURE_MIN_SIDE_M of its longer side. A wall between two rooms
# bounds both; one whose end only reaches a room's corner (a reach's span of its cells) bounds
# neither end room; the floor under every room bounds each.
STRUCTURE_REACH_M = 0.3
STRUCTURE_MIN_SIDE_M = 0.5


def rooms_bounded(places: Places, lo: np.ndarray, hi: np.ndarray) -> list[int]:
    """Rule "a room's structure" (STRUCTURE_REACH_M, STRUCTURE_MIN_SIDE_M): the labels of the
    rooms a floor's or wall's gravity-frame footprint, (a, b) corners `lo` and `hi`, bounds."""
    fm = places.floor
    if fm is None:
        return []
    lo, hi = np.asarray(lo, float)[:2], np.asarray(hi, float)[:2]
    shape = np.array(places.labels.shape)
    i0, j0 = np.clip(fm.cells_of(lo - STRUCTURE_REACH_M), 0, shape)
    i1, j1 = np.clip(fm.cells_of(hi + STRUCTURE_REACH_M) + 1, 0, shape)
    near = places.labels[i0:i1, j0:j1]
    along = 0 if hi[0] - lo[0] >= hi[1] - lo[1] else 1        # the footprint's longer side
    out = []
    for k in np.unique(near[near > 0]):
        cells = np.flatnonzero((near == k).any(axis=1 - along))
        if (cells[-1] - cells[0] + 1) * fm.cell >= STRUCTURE_MIN_SIDE_M:
            out.append(int(k))
    return out


def room_at(places: Places, ab: np.ndarray, reach_m: float = 1.5) -> np.ndarray:
    """The room label (0: none) of each (a, b) point: its cell's room, else the nearest room cell
    within `reach_m` (an object on a shelf stands over an occupied cell)."""
    from scipy import ndimage

    fm = places.floor
    assert fm is not None
    ab = np.asarray(ab, float).reshape(-1, 2)
    dist, (ii, jj) = ndimage.distance_transform_edt(places.labels == 0, return_indices=True)
    ij = fm.cells_of(ab)
    ij = np.clip(ij, 0, np.array(places.labels.shape) - 1)
    lab = places.labels[ii[ij[:, 0], ij[:, 1]], jj[ij[:, 0], ij[:, 1]]]
    far = dist[ij[:, 0], ij[:, 1]] * fm.cell > reach_m
    return np.where(far, 0, lab)
