"""Rooms from one walk (`sg3d build --rooms auto`) in the real store: a generated apartment gives
its rooms, doorways and every object in exactly one room; every real recording of ../shared/data
(each one room) gives exactly one room holding all its objects."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from sg3d.app.build import BuildRequest, build_room
from sg3d.graphdb.places import object_rooms, read_places
from sg3d.graphdb.values import room_id
from sg3d.ingest.pipeline import Settings

DATA = Path(__file__).resolve().parents[3] / "shared" / "data"
REAL = ("open3d-livingroom1-micro", "7scenes-redkitchen", "3dmatch-studyroom/fragment-1", "3dmatch-studyroom/fragment-2")


def _every_object_in_one_room(store, rid: str) -> list[dict]:
    rows = object_rooms(store, rid)
    assert rows, "the build kept no object"
    assert all(len(r["rooms"]) == 1 for r in rows), [r for r in rows if len(r["rooms"]) != 1]
    return rows


def test_a_walk_through_an_apartment_gives_its_rooms_doorways_and_each_object_in_one(store, tmp_path):
    pytest.importorskip("open3d", reason="the generated apartment needs the optional extra `synth` (open3d-cpu)")
    from benchmarks.synth import generate

    gt = generate("apartment", 4, tmp_path / "walk")
    summary = build_room(store, BuildRequest(sequence=tmp_path / "walk", room="walk", building="home", rooms="auto"),
                         Settings())
    rid = room_id("home", "walk")
    rooms = read_places(store, rid)
    assert len(rooms) == len(gt["apartment"]["rooms"]) == 5
    assert [r["name"] for r in rooms] == [f"room {k}" for k in range(1, 6)]
    assert all(r["area"] > 4 and len(r["polygon"]) >= 9 for r in rooms)
    doorways = {d["doorway"] for r in rooms for d in r["doorways"]}
    assert len(doorways) >= len([d for d in gt["apartment"]["doorways"] if d["kind"] == "door"])
    assert all(0.1 <= d["width"] < 2.5 for r in rooms for d in r["doorways"])
    rows = _every_object_in_one_room(store, rid)
    assert summary.rooms_found["objects_placed"] == len(rows)
    # each room's structure: the floor under every room, and every wall found bounds the rooms along it
    said = [(r["name"], sorted(s["label"] for s in r["structure"])) for r in rooms]
    floors = {r["id"] for r in rows if r["label"] == "floor"}
    walls = {r["id"] for r in rows if r["label"] == "wall"}
    assert floors and all(floors & {s["id"] for s in r["structure"]} for r in rooms), said
    assert walls and {s["id"] for r in rooms for s in r["structure"] if s["label"] == "wall"} == walls, said
    assert json.loads(json.dumps(summary.as_dict()))["rooms_found"]["doorways"] == len(doorways)
    from sg3d.app.rooms import delete_room

    delete_room(store, "home", "walk")                  # the found rooms go with their recorded room
    assert read_places(store, rid) == []


def test_a_build_with_room_name_writes_no_places_layer(store, tmp_path):
    seq = DATA / "open3d-livingroom1-micro"
    if not seq.exists():
        pytest.skip(f"{seq} is not there")
    summary = build_room(store, BuildRequest(sequence=seq, room="living", stop=60), Settings())
    assert summary.rooms_found is None
    assert read_places(store, room_id("default", "living")) == []


def test_a_writer_that_lost_its_lease_writes_no_rooms(store):
    """The rooms of a walk are written under the lease that guards the room's every publish
    (`sg3d map --rooms auto` writes them after each publish, `sg3d build --rooms auto` after its
    merges): a writer that lost the room changes nothing of the layer written before."""
    import time

    from sg3d.app.places import Walk, write_walk_rooms
    from sg3d.graphdb.lease import LeaseLost, RoomLease
    from sg3d.graphdb.merge import ensure_room
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames
    from sg3d.ingest.readers import open_sequence

    seq_dir = DATA / "open3d-livingroom1-micro"
    if not seq_dir.exists():
        pytest.skip(f"{seq_dir} is not there")
    seq = open_sequence(seq_dir)
    g = estimate_gravity(sample_frames(seq, 20, 0, len(seq)))
    walk = Walk(seq, 0, len(seq), g.up, g.floor_height, most=40)
    rid = room_id("home", "walked")
    ensure_room(store, "home", "walked")
    lease = RoomLease(store, "home", "walked", "map", "a paused map", ttl=0.2)
    lease.take()
    assert write_walk_rooms(store, rid, walk, fence=lease.fence)["rooms"]
    before = read_places(store, rid)
    assert len(before) == 1
    lease._stop.set()                       # it stops renewing (a paused process) and another map takes the room
    time.sleep(0.3)
    RoomLease(store, "home", "walked", "map", "next").take()
    with pytest.raises(LeaseLost, match="lost the lease"):
        write_walk_rooms(store, rid, walk, keep=True, fence=lease.fence)
    assert read_places(store, rid) == before


@pytest.mark.parametrize("name", REAL)
def test_every_real_recording_is_one_room(name):
    """The places layer of each real recording: one room (no build: the floor map and rooms only)."""
    from sg3d.app.places import find_places
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames
    from sg3d.ingest.readers import open_sequence

    seq_dir = DATA / name
    if not seq_dir.exists():
        pytest.skip(f"{seq_dir} is not there")
    seq = open_sequence(seq_dir)
    g = estimate_gravity(sample_frames(seq, 20, 0, len(seq)))
    places, _ = find_places(seq, 0, len(seq), g.up, g.floor_height)
    assert places is not None and len(places.rooms) == 1, places and [r.free_m2 for r in places.rooms]
    assert places.doorways == []


@pytest.mark.parametrize("name", REAL)
def test_a_real_recording_built_without_a_name_is_one_room_holding_all_its_objects(name, store, embedded_home):
    """`sg3d build SEQ --rooms auto` (no --room) of each real recording: the whole build (slow: the
    kitchen's 1000 frames take about a minute on a quiet machine)."""
    from click.testing import CliRunner

    from sg3d.cli import cli

    seq = DATA / name
    if not seq.exists():
        pytest.skip(f"{seq} is not there")
    r = CliRunner().invoke(cli, ["--home", str(embedded_home), "build", str(seq), "--rooms", "auto", "--json"])
    assert r.exit_code == 0, r.output[-2000:]
    found = json.loads(r.output)["rooms_found"]
    rid = room_id("default", seq.name)
    rooms = read_places(store, rid)
    assert len(rooms) == 1 and len(found["rooms"]) == 1, found
    rows = _every_object_in_one_room(store, rid)
    assert {r["rooms"][0] for r in rows} == {"room 1"}
    assert sorted(rooms[0]["objects"]) == sorted(r["id"] for r in rows)
    assert found["objects_placed"] == len(rows) == store.read("object_count", room=rid)[0]["n"]


def test_build_without_room_or_rooms_auto_is_one_error_line(tmp_path):
    from click.testing import CliRunner

    from sg3d.cli import cli

    r = CliRunner().invoke(cli, ["build", str(tmp_path)])
    assert r.exit_code == 2
    assert "give --room NAME, or --rooms auto" in r.output


def test_questions_over_the_rooms_of_a_walk(store, house):
    """"how many rooms", "where is X" name the rooms found in a walk, with their guessed kinds;
    a building without such a layer answers as before."""
    from sg3d.graphdb.places import write_places
    from sg3d.queries.vqa import answer

    before = answer(store, "how many rooms are there?", building="home").text
    assert before.startswith("2 rooms")
    rid = room_id("home", "kitchen")
    rooms = [{"id": f"{rid}#{k}", "name": f"room {k}", "polygon": [0.0] * 12, "area": 12.0, "free_area": 9.0,
              "x": 0.0, "y": 0.0, "z": 0.0, "kind_guess": kind, "kind_evidence": evidence}
             for k, kind, evidence in ((1, "kitchen", ["sink"]), (2, "office", ["tv"]))]
    pairs = [{"object": house[k], "room": f"{rid}#{1 if k in ('sk', 'k1', 'b2') else 2}"}
             for k in ("c1", "c2", "c3", "t", "s", "u1", "u2", "b1", "b2", "b3", "f1", "k1", "sp", "m", "sk")]
    doorways = [{"id": f"{rid}#doorway 1", "a": f"{rid}#1", "b": f"{rid}#2", "x": 1.0, "y": 0.0, "z": 0.0,
                 "width": 0.9}]
    def revision() -> int:
        return next(r["revision"] for r in store.read("room_revisions") if r["id"] == rid)

    before_write = revision()
    write_places(store, rid, rooms, doorways, pairs)
    assert revision() > before_write                 # cached answers over the room are not served over it
    assert [r["doorways"][0]["room"] for r in read_places(store, rid)] == ["room 2", "room 1"]
    text = answer(store, "how many rooms are there?", building="home").text
    assert text.startswith("3 rooms") and "room 1 of the kitchen (looks like a kitchen)" in text, text
    assert "living room" in text
    where = answer(store, "where is the sink?", building="home").text
    assert "room 1 (looks like a kitchen: sink) of the kitchen" in where, where
    which = answer(store, "which room is the sink in?", building="home").text
    assert which.startswith("room 1 (looks like a kitchen: sink) of the kitchen (1 sink)"), which


def _true_room_at(gt: dict):
    """world point -> the id of the generated apartment's room whose footprint holds it, or None."""
    import numpy as np
    from matplotlib.path import Path as Polygon

    T = np.asarray(gt["room_to_world"], float)
    rooms = [(r["id"], Polygon(r["polygon"])) for r in gt["apartment"]["rooms"]]

    def at(p) -> str | None:
        xy = ((np.asarray(p, float) - T[:3, 3]) @ T[:3, :3])[:2]
        return next((rid for rid, poly in rooms if poly.contains_point(xy)), None)
    return at


def test_a_map_of_an_apartment_written_at_30_fps_grows_its_rooms_and_ends_with_the_builds(store, tmp_path):
    """`sg3d map --rooms auto` of a generated apartment written as a folder at 30 frames/s: rooms
    appear while it is written, a room keeps its id and name across publishes (its middle stays in
    one true room while it grows), and at the end the rooms are the build's (footprints, doorways,
    objects held)."""
    pytest.importorskip("open3d", reason="the generated apartment needs the optional extra `synth` (open3d-cpu)")
    import threading
    import time

    import numpy as np

    from benchmarks.live_writer import write_live
    from benchmarks.synth import generate
    from sg3d.app.mapping import MapRequest, map_room

    src, dst = tmp_path / "apartment", tmp_path / "live"
    generate("apartment", 4, src)
    dst.mkdir()
    mapped = room_id("default", "mapped")
    seen: list[tuple[bool, dict]] = []        # (still being written, {id: (name, middle)}) per look
    done = threading.Event()
    total = len(list(src.glob("*.color.*")))

    def hold(k: int) -> bool:
        # a loaded machine may fall behind a 30 frames/s walk: past its middle, the walk waits for
        # the first room (growth is judged here; the rate a quiet machine keeps is bench_walk's)
        return k >= total // 2 and not any(rooms for _, rooms in seen)

    writer = threading.Thread(target=write_live, args=(src, dst, 30.0, None, 1.0), kwargs={"hold": hold}, daemon=True)

    def look() -> None:
        while not done.is_set():
            rooms = read_places(store, mapped)
            seen.append((writer.is_alive(), {r["id"]: (r["name"], (r["x"], r["y"], r["z"])) for r in rooms}))
            time.sleep(0.2)

    watcher = threading.Thread(target=look, daemon=True)
    writer.start()
    watcher.start()
    try:
        summary = map_room(store, MapRequest(dst, "mapped", publish_every=0.5, stop_when_idle=2.0, rooms="auto"),
                           Settings())
    finally:
        done.set()
        watcher.join()
    writer.join()
    while_written = [len(rooms) for alive, rooms in seen if alive]
    assert while_written and max(while_written) > 0, "no room appeared while the apartment was written"
    assert max(while_written) > min(while_written)                # they appear as the walk enters them
    assert summary.final["as_build"] and summary.final["rooms_found"]["rooms"]
    true_room = _true_room_at(json.loads((src / "ground_truth.json").read_text()))
    for rid in {rid for _, rooms in seen for rid in rooms}:
        names = {rooms[rid][0] for _, rooms in seen if rid in rooms}
        truly = {true_room(rooms[rid][1]) for _, rooms in seen if rid in rooms} - {None}
        assert len(names) == 1 and len(truly) <= 1, (rid, names, truly)     # one room all along
    build_room(store, BuildRequest(sequence=dst, room="built", rooms="auto"), Settings())
    live, built = read_places(store, mapped), read_places(store, room_id("default", "built"))

    def shape(rooms: list[dict]) -> list[tuple]:
        return sorted((round(r["area"], 3), np.round(r["polygon"], 3).tolist(), len(r["objects"]), len(r["doorways"]))
                      for r in rooms)

    assert len(live) == len(built) >= 4
    assert shape(live) == shape(built)
