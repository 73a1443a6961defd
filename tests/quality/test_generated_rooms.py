"""Generated rooms with exact ground truth (benchmarks.synth), built with default settings into
the real store and judged like `bench_rooms --generated`: the floor is found where the frames saw
it and only there, and a tabletop scan keeps its desk, top included, as an object."""
from __future__ import annotations

import pytest

pytest.importorskip("open3d", reason="the generated rooms need the optional extra `synth` (open3d-cpu)")

from benchmarks.bench_rooms import build_generated  # noqa: E402


def test_a_desk_scan_never_sees_the_floor_and_keeps_the_desk(store, tmp_path):
    row = build_generated(store, "desk", 1, tmp_path, frames=60)
    assert not row["floor_seen"]
    assert row["floor_said"] == "not seen"
    assert row["focus_object"] is True, row["missing"]
    assert row["flat_found"] >= 1, row["missing"]         # a keyboard, a phone or papers on the desk


def test_a_walk_around_a_room_finds_its_floor_and_its_walls(store, tmp_path):
    """At 320 x 240 the far walls' normals are too noisy for the vote: the fitted walls find them."""
    row = build_generated(store, "room", 0, tmp_path, frames=60)
    assert row["floor_seen"] and row["floor_right"], row["floor_said"]
    assert row["walls_found"] == row["walls_seen"] == 4, row
    assert row["walls_wrong"] == 0, row


def test_a_plane_slanted_across_a_found_wall_cuts_nothing_away(store, tmp_path):
    """Tried further down the vote, a plane 5 degrees across the south wall, fitted to its noisy
    remainder and a counter's front, would be a wall of its own and cut the bottle standing on the
    counter away; walls do not cross (`structure.same_wall`), so the bottle is found."""
    row = build_generated(store, "room", 21, tmp_path, frames=80)
    assert row["missing"].count("bottle") <= 3, row["missing"]
    assert row["matched"] >= 11, row


def test_a_robot_camera_a_foot_above_the_floor_finds_the_floor_and_the_walls_behind_the_furniture(store, tmp_path):
    """From 0.3 m the walls are 3-4 m away, their normals too noisy for the vote, and the beds'
    and tables' sides near the camera fill the fit's vote bins: a plane found to be no wall votes
    no more (`structure.rejected_votes`), so the far walls are fitted and the pieces of them
    are no objects."""
    row = build_generated(store, "robot", 2, tmp_path, frames=60)
    assert row["floor_seen"] and row["floor_right"], row["floor_said"]
    assert row["walls_found"] >= 3, row                  # the west and south walls behind the bed and the counter
    assert row["nodes"] - row["matched"] <= 15, row       # no pieces of those walls among the objects


def test_a_robot_camera_keeps_a_beds_side_and_not_the_chair_the_detector_named_on_it(store, tmp_path):
    """From 0.3 m the detector names pieces of a bed's side "chair"; the side is one face twice as
    long as either box (`discovery.face_part`), so the named chairs on it are no nodes: 9 objects
    match no thing at most (11 with them)."""
    row = build_generated(store, "robot", 12, tmp_path, frames=60)
    assert row["nodes"] - row["matched"] <= 9, row


def test_a_shelf_sweep_finds_the_things_on_the_boards_apart_from_the_bookcase(store, tmp_path):
    """Things standing on a bookcase's boards touch its sides and back; cut from it at the boards
    (`shelves.split_frame`), they are objects of their own, ON the bookcase."""
    row = build_generated(store, "shelf", 3, tmp_path, frames=60)
    assert row["tall_found"] >= row["tall"] // 2 + 1, row["missing"]
    assert row["matched"] >= 0.6 * row["nodes"], row
