"""Per-room tallies (sg3d/graphdb/tally.py): kept by the merge transaction, equal to a recount of the
objects, rolled back with a failed merge, and what store-wide counts read."""
from __future__ import annotations

import json
from collections import Counter

import pytest

from sg3d.graphdb.merge import merge_in_tx, merge_local_graph
from sg3d.graphdb.tally import rebuild_tallies
from sg3d.graphdb.values import room_id
from sg3d.queries.vqa import answer
from tests.cli_helpers import sg3d
from tests.factories import graph, hist_of, obj


def tallies(store) -> dict[tuple, int]:
    keys, rows = store.run_raw("MATCH (t:Tally) WHERE t.n <> 0 RETURN t.room, t.label, t.colour, t.n")
    return {(r[0], r[1], r[2]): r[3] for r in rows}


def recount(store) -> dict[tuple, int]:
    """Objects per (room, label, colour) and (room, label, '') straight from the Object records."""
    keys, rows = store.run_raw("MATCH (o:Object) RETURN o.room, o.label, o.colour")
    out = Counter()
    for room, label, colour in rows:
        out[(room, label, "")] += 1
        out[(room, label, colour)] += 1
    return dict(out)


def counts(store, labels, colour=None, rooms=None) -> dict[str, int]:
    return {r["label"]: r["n"] for r in store.read("vqa_count", labels=labels, colour=colour, rooms=rooms)}


@pytest.fixture
def mixed(store):
    """Creates in two rooms, a relabel (cup -> bowl), a recolour and a fold of two table parts."""
    merge_local_graph(store, graph([obj("c", "cup", (0.0, 0.0, 1.0), scores=[0.5]),
                                    obj("m", "cup", (2.0, 0.0, 1.0), colour="red", hist=hist_of({1: 100})),
                                    obj("h", "chair", (4.0, 0.0, 1.0), colour="black")]))
    merge_local_graph(store, graph([obj("c", "cup", (0.0, 0.0, 1.0))], room="office"))
    # a better view of the first cup says bowl: the node is relabelled
    r = merge_local_graph(store, graph([obj("b", "bowl", (0.01, 0.0, 1.0), labels=["bowl", "cup"],
                                            scores=[0.95, 0.4])]))
    assert r.updated == 1
    hist = hist_of({30: 500})
    for x in (-1.0, 1.0):
        merge_local_graph(store, graph([obj(f"t{x}", "dining table", (x, 3.0, 1.0), size=(0.8, 0.8, 0.1),
                                            hist=hist, colour="brown")]))
    whole = obj("w", "dining table", (0.0, 3.0, 1.0), size=(2.4, 0.8, 0.1), hist=hist, colour="brown")
    assert merge_local_graph(store, graph([whole])).absorbed == 1
    return store


def test_merges_keep_the_tallies_equal_to_a_recount(mixed):
    assert tallies(mixed) == recount(mixed)
    kitchen = room_id("home", "kitchen")
    assert tallies(mixed)[(kitchen, "bowl", "")] == 1 and (kitchen, "cup", "white") not in tallies(mixed)
    assert tallies(mixed)[(kitchen, "dining table", "")] == 1


def test_store_wide_counts_come_from_the_tallies(mixed):
    assert counts(mixed, ["cup", "bowl", "dining table"]) == {"cup": 2, "bowl": 1, "dining table": 1}
    assert counts(mixed, ["cup"], colour="red") == {"cup": 1}
    assert counts(mixed, ["cup"], rooms=[room_id("home", "office")]) == {"cup": 1}
    anything = {r["label"]: r["n"] for r in mixed.read("vqa_count_any", colour=None, rooms=None)}
    assert anything == {"cup": 2, "bowl": 1, "dining table": 1, "chair": 1}
    # a tally says 7 cups now: the answer follows the tally, not the Object records
    mixed.run_raw("MATCH (t:Tally) WHERE t.label = 'cup' AND t.colour = '' AND t.room = $r SET t.n = 6",
                  {"r": room_id("home", "office")}, write=True)
    assert answer(mixed, "how many cups are there?").value == 7
    assert rebuild_tallies(mixed) == len(recount(mixed))
    assert tallies(mixed) == recount(mixed)
    assert answer(mixed, "how many cups are there?").value == 2


def test_a_failed_merge_leaves_the_tallies_as_they_were(mixed):
    before = tallies(mixed)

    def fail(tx):
        merge_in_tx(tx, graph([obj("n", "vase", (9.0, 0.0, 1.0)), obj("k", "cup", (5.0, 5.0, 1.0))]))
        raise RuntimeError("after the merge's writes")

    with pytest.raises(RuntimeError):
        mixed.execute_write(fail)
    assert tallies(mixed) == before


def test_sg3d_db_rebuild_tallies_repairs_stale_tallies(mixed, embedded_home):
    """Objects edited by hand leave the tallies stale; `sg3d db rebuild-tallies` recounts them."""
    mixed.run_raw("MATCH (o:Object) WHERE o.label = 'chair' SET o.label = 'couch'", write=True)
    mixed.run_raw("MATCH (t:Tally) WHERE t.label = 'cup' SET t.n = t.n + 5", write=True)
    assert tallies(mixed) != recount(mixed)
    assert answer(mixed, "how many couches are there?").value == 0
    r = sg3d(embedded_home, "db", "rebuild-tallies", "--json", timeout=300)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["objects"] == 5 and out["tallies"] == len(recount(mixed))
    assert tallies(mixed) == recount(mixed)
    assert answer(mixed, "how many couches are there?").value == 1
    assert answer(mixed, "how many cups are there?").value == 2


def test_a_local_graph_of_more_objects_than_one_create_batch_is_created_whole(store):
    from sg3d.graphdb.tally import CREATE_BATCH

    n = CREATE_BATCH + 37        # two statements; the tallies ride with the last
    objs = [obj(f"o{i}", "cup" if i % 2 else "book", (i * 2.0, 0.0, 1.0), colour="red" if i % 3 else "white")
            for i in range(n)]
    report = merge_local_graph(store, graph(objs, room="hall"))
    assert report.created == n
    _, rows = store.run_raw("MATCH (o:Object) RETURN count(o)")
    assert rows[0][0] == n
    assert tallies(store) == recount(store)
    hall = room_id("home", "hall")
    assert tallies(store)[(hall, "cup", "")] + tallies(store)[(hall, "book", "")] == n
