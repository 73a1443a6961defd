"""A room found in a walk keeps its id and name across a live map's publishes (`kept_names`), new
rooms are numbered on, and the live budget of the rooms step is pinned."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.app import places as app_places
from sg3d.app.places import KEEP_REACH_M, _ids, kept_names
from sg3d.ingest.places import segment_rooms
from sg3d.ingest.places.floor_map import FREE, OCCUPIED, FloorMap

BASIS = np.eye(3)          # gravity frame = world frame: a room's middle (x, y) is its (a, b)


def _two_rooms() -> FloorMap:
    """Two 4 x 4 m rooms side by side, a 0.9 m door in the wall at a = 4 m, and 6 m of solid
    ground beyond their north wall (b > 4 m)."""
    cell = 0.05
    state = np.full((162, 200), OCCUPIED, np.int8)
    state[1:-1, 1:80] = FREE
    state[80:82, :31] = OCCUPIED
    state[80:82, 49:] = OCCUPIED
    return FloorMap(state, np.zeros(2), cell)


def _before(*rooms):
    return [{"id": f"home/w#{k}", "name": name, "x": x, "y": y, "z": 0.0} for k, name, x, y in rooms]


PLACES = segment_rooms(_two_rooms())


def _label_at(a: float, b: float) -> int:
    from sg3d.ingest.places import room_at

    return int(room_at(PLACES, np.array([[a, b]]))[0])


def test_a_room_whose_earlier_middle_lies_in_it_keeps_its_id_and_name():
    kept = kept_names(PLACES, BASIS, _before((3, "kitchen", 2.0, 2.0)))
    assert kept == {_label_at(2.0, 2.0): ("home/w#3", "kitchen")}
    # the other room is new: numbered after every kept one
    ids = _ids("home/w", PLACES, kept)
    assert ids[_label_at(6.0, 2.0)] == ("home/w#4", "room 4")


def test_of_two_rooms_that_merged_the_one_numbered_first_stays():
    kept = kept_names(PLACES, BASIS, _before((5, "room 5", 1.0, 1.0), (2, "room 2", 3.0, 3.0)))
    assert kept == {_label_at(2.0, 2.0): ("home/w#2", "room 2")}


def test_an_earlier_middle_is_kept_within_the_reach_only():
    # north of the rooms' last cell: within KEEP_REACH_M the room is found, past it none
    edge = (np.nonzero((PLACES.labels > 0).any(axis=0))[0].max() + 0.5) * PLACES.floor.cell
    near = kept_names(PLACES, BASIS, _before((1, "room 1", 2.0, edge + KEEP_REACH_M - 0.1)))
    far = kept_names(PLACES, BASIS, _before((1, "room 1", 2.0, edge + KEEP_REACH_M + 0.1)))
    assert near and not far


def test_a_build_numbers_its_rooms_in_order():
    assert sorted(n for _, n in _ids("home/w", PLACES, None).values()) == ["room 1", "room 2"]


def test_the_live_rooms_budget():
    assert KEEP_REACH_M == pytest.approx(1.0)
    assert 1.0 <= app_places.ROOMS_EVERY_S <= 5.0
    assert 30 <= app_places.LIVE_FRAMES < app_places.MAX_FRAMES
