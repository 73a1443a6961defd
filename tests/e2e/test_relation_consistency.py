"""Stored relations stay contradiction-free and canonical across merges (real embedded store)."""
from __future__ import annotations

from sg3d.core.model import RELATION_TYPES
from sg3d.graphdb import cypher
from sg3d.graphdb.checks import relation_contradictions
from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from tests.factories import graph, hist_of, obj

ROOM = room_id("home", "kitchen")


def cup():
    return obj("c", "cup", (0.0, 0.0, 1.0))


def table():
    return obj("t", "dining table", (0.0, -0.3, 0.8), size=(1.5, 0.8, 0.7), hist=hist_of({30: 500}), colour="brown")


def chair():
    return obj("h", "chair", (0.0, 0.8, 0.45), size=(0.45, 0.45, 0.9), hist=hist_of({200: 100}), colour="black")


def edges(store):
    return {(r["s"], r["type"], r["o"]): r["count"]
            for r in store.read("relation_all", room=ROOM, types=list(RELATION_TYPES))}


def ids(store):
    return {r["o"]["label"]: r["o"]["id"] for r in store.read("object_all", room=ROOM)}


def clean(store):
    check = relation_contradictions(store, ROOM)
    return (check["contradictory_pairs"], check["non_canonical_symmetric"], check["viewpoint_edges"]) == (0, 0, 0)


def test_graphs_merged_in_contradicting_order_keep_the_better_supported_relation(store):
    merge_local_graph(store, graph([cup(), table()], relations=[("t", "ON", "c", 0.9)]))      # wrong, first
    merge_local_graph(store, graph([cup(), table()], relations=[("c", "ON", "t", 0.7)]))
    merge_local_graph(store, graph([cup(), table()], relations=[("c", "ON", "t", 0.8), ("t", "UNDER", "c", 0.5)]))
    n = ids(store)
    assert len(n) == 2
    got = edges(store)
    assert got == {(n["cup"], "ON", n["dining table"]): 2}
    assert clean(store)
    assert relation_contradictions(store, ROOM)["pairs"] == 1


def test_above_and_below_the_same_way_resolve_to_one_statement_with_its_inverse(store):
    merge_local_graph(store, graph([cup(), table()], relations=[("c", "ABOVE", "t", 0.6)]))
    merge_local_graph(store, graph([cup(), table()], relations=[("c", "ABOVE", "t", 0.6)]))
    merge_local_graph(store, graph([cup(), table()], relations=[("c", "BELOW", "t", 0.9)]))
    n = ids(store)
    assert edges(store) == {(n["cup"], "ABOVE", n["dining table"]): 2, (n["dining table"], "BELOW", n["cup"]): 2}
    assert clean(store)


def test_symmetric_relations_are_stored_once_by_global_id_and_read_both_ways(store):
    merge_local_graph(store, graph([chair(), table()], relations=[("h", "NEXT_TO", "t", 0.8)]))
    merge_local_graph(store, graph([chair(), table()], relations=[("t", "NEXT_TO", "h", 0.6)]))
    merge_local_graph(store, graph([chair(), table()], relations=[("h", "NEAR", "t", 0.9)]))
    n = ids(store)
    lo, hi = sorted((n["chair"], n["dining table"]))
    # one edge; NEAR was evidence for the same side-by-side placement
    assert edges(store) == {(lo, "NEXT_TO", hi): 3}
    assert clean(store)


def test_viewpoint_relations_are_never_stored(store):
    merge_local_graph(store, graph([chair(), table()], relations=[("h", "IN_FRONT_OF", "t", 0.9),
                                                                  ("t", "BEHIND", "h", 0.9)]))
    assert edges(store) == {}
    assert relation_contradictions(store, ROOM)["viewpoint_edges"] == 0


def test_the_check_finds_contradictions_written_behind_the_merges_back(store):
    merge_local_graph(store, graph([cup(), table(), chair()]))
    n = ids(store)
    lo, hi = sorted((n["chair"], n["dining table"]))
    at = 0.0

    def write(rel_type, s, o):
        store.execute_write(lambda tx: tx.run(cypher.render("relation_merge", rel_type),
                                              rows=[{"s": s, "o": o, "score": 0.5, "at": at}]).consume())

    write("ON", n["cup"], n["dining table"])
    write("ON", n["dining table"], n["cup"])
    write("NEXT_TO", hi, lo)
    write("IN_FRONT_OF", n["cup"], n["chair"])
    check = relation_contradictions(store, ROOM)
    assert check["contradictory_pairs"] == 1
    assert check["non_canonical_symmetric"] == 1
    assert check["viewpoint_edges"] == 1
    assert sorted(check["examples"][0][:2]) == sorted((n["cup"], n["dining table"]))
    # the next merge touching these nodes repairs them
    merge_local_graph(store, graph([cup(), table(), chair()], relations=[("c", "ON", "t", 0.9)]))
    assert clean(store)
    got = edges(store)
    assert (n["cup"], "ON", n["dining table"]) in got and (lo, "NEXT_TO", hi) in got
