"""The places layer's rules (sg3d.ingest.places): the floor map's cell states and the rooms and
doorways segmented from it, each threshold pinned on both sides."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.places import Places, PlacesConfig, floor_map, room_at, rooms_bounded, rooms_of_walk, segment_rooms
from sg3d.ingest.places.floor_map import FREE, OCCUPIED, UNKNOWN, FloorMap, obstacle_cells
from sg3d.ingest.places.rooms import STRUCTURE_MIN_SIDE_M, STRUCTURE_REACH_M, merge_small, own_room, passage_width

CFG = PlacesConfig()


def _plan(walls: list[tuple[float, float, float, float]], size=(10.0, 6.0), cell=0.05) -> FloorMap:
    """A floor map of free floor with occupied rectangles (a0, b0, a1, b1) in metres."""
    na, nb = int(round(size[0] / cell)), int(round(size[1] / cell))
    state = np.full((na, nb), FREE, np.int8)
    state[[0, -1], :] = OCCUPIED
    state[:, [0, -1]] = OCCUPIED
    for a0, b0, a1, b1 in walls:
        state[int(round(a0 / cell)):int(round(a1 / cell)), int(round(b0 / cell)):int(round(b1 / cell))] = OCCUPIED
    return FloorMap(state, np.zeros(2), cell)


def _two_rooms(gap_m: float, lengths=(4.0, 4.0), depth=4.0) -> FloorMap:
    """Two rooms side by side joined by a gap of gap_m in the wall between them."""
    x = lengths[0]
    g0 = depth / 2 - gap_m / 2
    return _plan([(x, 0, x + 0.1, g0), (x, g0 + gap_m, x + 0.1, depth)], size=(sum(lengths) + 0.1, depth))


def test_a_cell_is_occupied_from_its_minimum_count_of_obstacle_points():
    counts = np.array([CFG.obstacle_min_points - 1, CFG.obstacle_min_points])
    assert obstacle_cells(counts, CFG).tolist() == [False, True]


def test_floor_points_free_obstacle_points_occupy_and_the_rest_is_unknown():
    rng = np.random.default_rng(0)
    floor = np.c_[rng.uniform(0, 2, (4000, 2)), rng.normal(0, 0.01, 4000)]
    box = np.c_[rng.uniform(0.5, 0.7, (400, 2)), rng.uniform(0.2, 0.8, 400)]
    above = np.c_[rng.uniform(1.5, 1.7, (400, 2)), np.full(400, CFG.obstacle_high_m + 0.1)]   # a lintel
    fm = floor_map(np.concatenate([floor, box, above]), np.zeros((0, 3)))
    at = lambda a, b: fm.state[tuple(fm.cells_of(np.array([a, b])))]     # noqa: E731
    assert at(0.6, 0.6) == OCCUPIED
    assert at(1.6, 1.6) == FREE
    assert at(1.0, 1.0) == FREE
    assert at(2.4, 2.4) == UNKNOWN


def test_obstacle_band_limits():
    pts = np.array([[0.5, 0.5, CFG.obstacle_low_m - 0.01]] * 5 + [[1.0, 1.0, CFG.obstacle_low_m + 0.01]] * 5
                   + [[1.5, 1.5, CFG.obstacle_high_m - 0.01]] * 5 + [[2.0, 2.0, CFG.obstacle_high_m + 0.01]] * 5)
    fm = floor_map(pts, np.zeros((0, 3)))
    states = [fm.state[tuple(fm.cells_of(p[:2]))] for p in pts[::5]]
    assert states == [UNKNOWN, OCCUPIED, OCCUPIED, UNKNOWN]


def test_the_floor_round_a_camera_is_free_within_its_reach():
    pts = np.array([[5.0, 5.0, 1.0]] * 3)     # one obstacle far away, only to span a grid
    fm = floor_map(pts, np.array([[1.0, 1.0, 1.45]]))
    at = lambda d: fm.state[tuple(fm.cells_of(np.array([1.0 + d, 1.0])))]      # noqa: E731
    assert at(CFG.camera_free_m - 0.06) == FREE
    assert at(CFG.camera_free_m + 0.06) == UNKNOWN


def test_own_room_needs_both_the_dynamic_and_the_ratio():
    peak = 1.0
    assert own_room(peak, CFG.passage_ratio * peak - 0.01, CFG)
    assert not own_room(peak, CFG.passage_ratio * peak + 0.01, CFG)
    small = 0.5                                     # ratio passes, the dynamic decides
    saddle = small - CFG.min_dynamic_m
    assert own_room(small, saddle - 0.01, CFG) and not own_room(small, saddle + 0.01, CFG)


def test_two_rooms_joined_by_a_door_are_two_rooms_with_one_doorway():
    places = segment_rooms(_two_rooms(0.9))
    assert len(places.rooms) == 2
    assert len(places.doorways) == 1
    d = places.doorways[0]
    assert d.position[0] == pytest.approx(4.05, abs=0.15) and d.position[1] == pytest.approx(2.0, abs=0.15)
    assert d.width_m == pytest.approx(0.9, abs=0.15)
    a, b = room_at(places, np.array([[2.0, 2.0], [6.0, 2.0]]))
    assert a != b and {a, b} == {1, 2}


def test_rooms_joined_by_an_opening_as_wide_as_them_are_one_room():
    assert len(segment_rooms(_two_rooms(3.6)).rooms) == 1


def test_a_corridor_with_doors_into_rooms_is_its_own_room():
    # a 1.3 m corridor along b in [4, 5.3] with two 4 x 4 rooms south of it, doors 0.9 m wide
    walls = [(0, 3.9, 1.0, 4.0), (1.9, 3.9, 5.0, 4.0), (5.0, 3.9, 6.0, 4.0), (6.9, 3.9, 10.0, 4.0),
             (4.9, 0, 5.0, 3.9)]
    places = segment_rooms(_plan(walls, size=(10.0, 5.35)))
    assert len(places.rooms) == 3
    assert len(places.doorways) == 2
    corridor = room_at(places, np.array([[5.0, 4.6]]))[0]
    assert all(corridor in (d.a, d.b) for d in places.doorways)


@pytest.mark.parametrize("area, joins", [(CFG.min_room_area_m2 - 0.1, True), (CFG.min_room_area_m2 + 0.1, False)])
def test_a_room_smaller_than_the_minimum_joins_its_neighbour(area, joins):
    cell = 0.05
    cells = int(round(area / cell ** 2))
    labels = np.ones((100, 100), np.int32)
    side = int(np.sqrt(cells))
    labels[:side, :side] = 2
    extra = cells - side * side
    labels[side, :extra] = 2
    out = merge_small(labels.copy(), cell, CFG)
    assert (2 not in out) == joins


def test_passage_width_is_the_extent_of_the_border_cells():
    cells = np.array([[0.0, b] for b in np.arange(0, 0.9, 0.05)])
    assert passage_width(cells, 0.05) == pytest.approx(0.9, abs=1e-6)


def test_rooms_of_walk_runs_from_points_and_cameras():
    rng = np.random.default_rng(1)
    floor = np.c_[rng.uniform(0, 4, (20000, 2)), np.zeros(20000)]
    wall = np.c_[np.full(2000, 2.0), rng.uniform(0, 4, 2000), rng.uniform(0.2, 1.8, 2000)]
    wall = wall[(wall[:, 1] < 1.55) | (wall[:, 1] > 2.45)]
    places = rooms_of_walk(np.concatenate([floor, wall]), np.array([[1.0, 2.0, 1.4], [3.0, 2.0, 1.4]]))
    assert len(places.rooms) == 2 and len(places.doorways) == 1


def test_a_border_narrower_than_the_minimum_is_no_doorway():
    from sg3d.ingest.places.rooms import doorways

    fm = _plan([])
    labels = np.zeros(fm.state.shape, np.int32)
    labels[:40, :] = 1
    labels[40:, :] = 2
    labels[40:, 20:] = 0          # the rooms touch along a border of n cells from b = 0
    labels[:40, 20:] = 0
    for n, kept in ((int(CFG.min_doorway_m / fm.cell) - 1, False), (int(CFG.min_doorway_m / fm.cell) + 1, True)):
        lab = labels.copy()
        lab[39, n:] = 0
        assert bool(doorways(lab, fm, CFG)) == kept, n


def test_obstacle_cells_inside_a_border_split_it_only_past_the_passage_gap():
    from sg3d.ingest.places.rooms import borders

    gap = int(round(CFG.passage_gap_m / 0.05))
    for hole, parts in ((gap, 1), (gap + 2, 2)):
        labels = np.zeros((20, 60), np.int32)
        labels[:10, :] = 1
        labels[10:, :] = 2
        labels[9, 20:20 + hole] = 0           # obstacle cells in the border between the two rooms
        labels[9, :10] = 0
        labels[9, 40:] = 0
        assert len(borders(labels, gap)) == parts, hole


def test_a_rooms_outline_left_open_to_the_unseen_is_its_unseen_share():
    from sg3d.ingest.places.rooms import unseen_outline

    state = np.full((12, 12), UNKNOWN, np.int8)
    state[1:11, 1:11] = FREE
    state[1:11, 1] = OCCUPIED                     # walls seen on three sides, one side left open
    state[1, 1:11] = OCCUPIED
    state[10, 1:11] = OCCUPIED
    extent = np.zeros((12, 12), np.int32)
    extent[1:11, 1:11] = 1
    share = unseen_outline(extent, state, 1)
    outline = 36                                  # the 10 x 10 room's border cells
    assert share == pytest.approx(round(8 / outline, 3))   # the open side's free cells, corners are walls
    state[1:11, 10] = OCCUPIED
    assert unseen_outline(extent, state, 1) == 0.0
    assert unseen_outline(extent, state, 2) == 0.0           # no such room


def _one_room_places() -> Places:
    """Room 1 alone: cells a in [0, 4) m, b in [0, 4) m (5 cm cells), nothing else."""
    labels = np.zeros((200, 200), np.int32)
    labels[:80, :80] = 1
    fm = FloorMap(np.full(labels.shape, FREE, np.int8), np.zeros(2), 0.05)
    return Places([], [], labels, fm)


def test_a_wall_bounds_a_room_within_its_reach_and_no_further():
    """A wall along b (0.1 m thick, 4 m long) beside the room's side at a = 4 m: within
    STRUCTURE_REACH_M of the room's cells it bounds it, past it (by a cell's quantisation) not."""
    places = _one_room_places()
    reach = STRUCTURE_REACH_M
    for gap, bounds in ((0.0, [1]), (reach - 0.01, [1]), (reach + 0.01, [])):
        assert rooms_bounded(places, np.array([4.0 + gap, 0.0]), np.array([4.1 + gap, 4.0])) == bounds, gap


def test_a_wall_bounds_a_room_along_at_least_the_minimum_side():
    """A wall along a beyond the room's side at b = 4 m, starting at a0: the room's cells within
    its reach run 4.0 - (a0 - STRUCTURE_REACH_M) m along it; at least STRUCTURE_MIN_SIDE_M bounds
    the room (a wall meeting its corner does not)."""
    places = _one_room_places()
    a0 = 4.0 + STRUCTURE_REACH_M - STRUCTURE_MIN_SIDE_M
    for start, bounds in ((a0 - 0.01, [1]), (a0 + 0.06, []), (4.1, [])):
        assert rooms_bounded(places, np.array([start, 4.0]), np.array([start + 2.0, 4.1])) == bounds, start


def test_the_floor_and_the_wall_between_two_rooms_bound_both():
    places = segment_rooms(_two_rooms(0.9), CFG)
    assert [r.label for r in places.rooms] == [1, 2]
    assert rooms_bounded(places, np.array([0.0, 0.0]), np.array([8.1, 4.0])) == [1, 2]        # the floor
    assert rooms_bounded(places, np.array([4.0, 0.0]), np.array([4.1, 1.55])) == [1, 2]       # the wall between
    assert rooms_bounded(places, np.array([0.0, 0.0]), np.array([0.05, 4.0])) == [1]          # the far walls
    assert rooms_bounded(places, np.array([8.05, 0.0]), np.array([8.1, 4.0])) == [2]
