"""Re-scans of the real kitchen (issue #17): scan 1 = the kitchen; scan 2' = frames 500-999 only;
scan 2 = every frame with one cup painted out (colour) and its depth replaced by the table surface
behind it (tests/rescan_fixture.py). The cup is chosen from scan 1's graph, never from ground
truth. Takes about 3-4 minutes on two cores (three builds and the painting)."""
from __future__ import annotations

from collections import Counter

import pytest

from sg3d.graphdb.values import room_id
from tests.rescan_fixture import paint_out

ROOM = room_id("test", "kitchen")


def _build(store, sequence, start=0, stop=None) -> dict:
    from sg3d.app.build import BuildRequest, build_room
    from sg3d.ingest.pipeline import Settings

    return build_room(store, BuildRequest(sequence=sequence, room="kitchen", building="test", start=start,
                                          stop=stop), Settings())


def _objects(store) -> dict[str, dict]:
    _, rows = store.run_raw("MATCH (o:Object) WHERE o.room = $room RETURN o {.*}", {"room": ROOM})
    return {r[0]["id"]: r[0] for r in rows}


def _tallies(store) -> Counter:
    _, rows = store.run_raw("MATCH (t:Tally) WHERE t.room = $room AND t.n <> 0 RETURN t.label, t.colour, t.n",
                            {"room": ROOM})
    return Counter({(r[0], r[1]): r[2] for r in rows})


def _recount(objects: dict[str, dict]) -> Counter:
    out = Counter()
    for o in objects.values():
        if o.get("removed_at") is None:
            out[(o["label"], "")] += 1
            out[(o["label"], o["colour"])] += 1
    return out


def test_kitchen_rescans_remove_the_painted_cup_and_nothing_else(store, kitchen_dir, tmp_path):
    first = _build(store, kitchen_dir)
    scan1 = _objects(store)
    cups = [o for o in scan1.values() if o["label"] == "cup"]
    if not cups:
        pytest.skip("the first scan found no cup to take away")
    cup = max(cups, key=lambda o: (o["n_frames"], o["id"]))     # the best-seen cup of scan 1
    assert all(o["scans"] == [first["scan"]] for o in scan1.values())

    # scan 2: the cup painted out of every frame that shows it
    _, rows = store.run_raw("MATCH (r:Room {id: $room}) RETURN r.up", {"room": ROOM})
    painted = paint_out(kitchen_dir, tmp_path / "kitchen-without-cup", cup["box_centre"], cup["size"], rows[0][0])
    assert len(painted) > 50
    second = _build(store, tmp_path / "kitchen-without-cup")
    after = _objects(store)
    removed = {i: (o["label"], len(o["empty_frames"])) for i, o in after.items() if o.get("removed_at") is not None}
    assert set(removed) == {cup["id"]}, removed
    assert second["graph"]["objects_removed"] == 1 and second["graph"]["objects_moved"] == 0
    gone = after[cup["id"]]
    assert gone["removed_scan"] == second["scan"] and len(gone["empty_frames"]) >= 2
    assert set(gone["empty_frames"]) <= set(painted)            # the evidence: frames of the empty place
    # never deleted: a node leaves only by folding into the object a later view shows it was part of
    assert len(set(scan1) - set(after)) == second["graph"]["objects_folded"]
    # tallies: the removed cup is not counted, everything else is
    assert _tallies(store) == _recount(after)
    assert _tallies(store)[("cup", "")] == sum(1 for o in after.values()
                                               if o["label"] == "cup" and o.get("removed_at") is None)
    assert store.read("object_count", room=ROOM)[0]["n"] == len(after) - 1

    # the same scan again: nothing changes
    again = _build(store, tmp_path / "kitchen-without-cup")
    assert again["graph"]["merged_chunks"] == 0
    assert _objects(store) == after and _tallies(store) == _recount(after)

    # scan 2': the original frames 500-999 only. Nothing is removed, in particular nothing those
    # frames never look at (objects they did not re-observe keep their state), and nothing moves
    partial = _build(store, kitchen_dir, start=500, stop=1000)
    assert partial["scan"] not in (first["scan"], second["scan"])
    assert (partial["graph"]["objects_removed"], partial["graph"]["objects_moved"]) == (0, 0)
    final = _objects(store)
    not_seen = {i for i, o in final.items() if partial["scan"] not in (o.get("scans") or [])}
    assert not_seen and not_seen < set(final)                   # a partial view: some were not re-seen
    assert all(final[i].get("removed_at") == after[i].get("removed_at") for i in not_seen if i in after)
    assert _tallies(store) == _recount(final)
