"""Merge and update as Cypher transactions, against a real embedded ArcadeDB over Bolt."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.model import RELATION_TYPES
from sg3d.graphdb.merge import merge_in_tx, merge_local_graph
from sg3d.graphdb.values import room_id
from sg3d.merge.histograms import unpack_hist
from tests.factories import graph, hist_of, obj

ROOM = room_id("home", "kitchen")


def count(store):
    return store.read("object_count", room=ROOM)[0]["n"]


def objects(store):
    return [r["o"] for r in store.read("object_all", room=ROOM)]


def test_merging_the_same_local_graph_twice_is_idempotent(store):
    g = graph([obj("a", "cup", (0.0, 0.0, 1.0)), obj("b", "dining table", (0.0, -0.3, 1.0), size=(1.5, 0.8, 0.7),
                                                    hist=hist_of({30: 500}), colour="brown")],
              relations=[("a", "ON", "b", 0.9)])
    merge_local_graph(store, g)
    assert count(store) == 2
    report = merge_local_graph(store, g)
    assert report.updated == 2 and report.created == 0
    assert count(store) == 2
    rels = store.read("relation_all", room=ROOM, types=list(RELATION_TYPES))
    assert [(r["type"], r["count"]) for r in rels] == [("ON", 2)]


def test_two_views_of_one_cup_become_one_node_with_the_papers_update(store):
    h1, h2 = hist_of({7: 60, 100: 40}), hist_of({7: 50, 101: 30})
    first = obj("c1", "cup", (1.00, 0.50, 2.00), labels=["cup", "bowl"], scores=[0.8, 0.3],
                var=(0.010, 0.020, 0.030), n_points=100, hist=h1, thumbnail=b"old")
    second = obj("c2", "cup", (1.04, 0.48, 2.03), labels=["cup", "vase"], scores=[0.9, 0.2],
                 var=(0.020, 0.010, 0.010), n_points=300, hist=h2, thumbnail=b"new")
    merge_local_graph(store, graph([first]))
    report = merge_local_graph(store, graph([second]))
    assert (report.created, report.updated) == (0, 1)
    [node] = objects(store)
    # moments of the union of both point sets, computed independently of sg3d.merge.update
    m1, m2 = np.array(first.mean), np.array(second.mean)
    v1, v2 = np.array(first.var), np.array(second.var)
    mean = (100 * m1 + 300 * m2) / 400
    var = (100 * (v1 + m1 ** 2) + 300 * (v2 + m2 ** 2)) / 400 - mean ** 2
    assert np.allclose([node["x"], node["y"], node["z"]], mean)
    assert np.allclose(node["var"], var)
    assert node["n_points"] == 400
    assert np.allclose(unpack_hist(node["hist"]), h1 + h2)
    assert node["labels"][:2] == ["cup", "bowl"] and node["scores"][:2] == [0.9, 0.3]
    assert set(node["labels"]) == {"cup", "bowl", "vase"}
    assert bytes(node["thumbnail"]) == b"new"  # best label score came with the new view
    assert node["observations"] == 2


def test_a_mug_and_a_sofa_at_the_same_place_stay_two_nodes(store):
    mug = obj("m", "cup", (0.0, 0.0, 1.0), hist=hist_of({7: 100}))
    sofa = obj("s", "couch", (0.0, 0.0, 1.0), hist=hist_of({200: 100}), size=(2.0, 0.9, 0.8))
    merge_local_graph(store, graph([mug]))
    merge_local_graph(store, graph([sofa]))
    assert sorted(o["label"] for o in objects(store)) == ["couch", "cup"]


def test_same_label_far_apart_stays_two_nodes(store):
    merge_local_graph(store, graph([obj("a", "chair", (0.0, 0.0, 1.0))]))
    merge_local_graph(store, graph([obj("b", "chair", (3.0, 0.0, 1.0))]))
    assert count(store) == 2


def test_logged_key_is_merged_once(store):
    g = graph([obj("a", "cup", (0.0, 0.0, 1.0))], key="run1:0")
    assert not merge_local_graph(store, g).skipped
    assert merge_local_graph(store, g).skipped
    assert objects(store)[0]["observations"] == 1


def _snapshot(store):
    return objects(store), store.read("relation_all", room=ROOM, types=list(RELATION_TYPES))


def test_python_error_mid_merge_rolls_back(store):
    merge_local_graph(store, graph([obj("a", "cup", (0.0, 0.0, 1.0))]))
    before = _snapshot(store)
    bad = graph([obj("a", "cup", (0.0, 0.0, 1.0)), obj("t", "dining table", (2.0, 0.0, 1.0))],
                relations=[("a", "ON", "missing", 0.9)], key="bad")
    with pytest.raises(KeyError):
        merge_local_graph(store, bad)
    assert _snapshot(store) == before
    assert not store.read("merge_log_exists", key="bad")


def test_cypher_error_mid_merge_rolls_back(store):
    from neo4j.exceptions import CypherSyntaxError

    from sg3d.core.embedding import default_embedding

    merge_local_graph(store, graph([obj("a", "cup", (0.0, 0.0, 1.0))]))
    before = _snapshot(store)

    def merge_then_fail(tx):
        report = merge_in_tx(tx, graph([obj("n", "bowl", (5.0, 0.0, 1.0))], key="bad2"), default_embedding())
        assert report.created == 1
        tx.run("THIS IS NOT CYPHER").consume()

    with pytest.raises(CypherSyntaxError):
        store.execute_write(merge_then_fail)
    assert _snapshot(store) == before


def test_a_big_object_seen_in_parts_becomes_one_node_whose_box_grows(store):
    left = obj("l", "dining table", (-0.5, 0.0, 1.0), size=(1.0, 0.8, 0.1), hist=hist_of({30: 500}), colour="brown")
    right = obj("r", "dining table", (0.5, 0.0, 1.0), size=(1.0, 0.8, 0.1), hist=hist_of({30: 400, 31: 100}),
                colour="brown")
    merge_local_graph(store, graph([left]))
    merge_local_graph(store, graph([right]))
    [table] = objects(store)
    assert np.allclose(table["size"], (2.0, 0.8, 0.1))


def test_a_brown_chair_under_a_brown_table_stays_a_chair(store):
    table = obj("t", "dining table", (0.0, 0.0, 0.75), size=(2.0, 0.9, 0.1), hist=hist_of({30: 500}), colour="brown")
    chair = obj("c", "chair", (0.3, 0.2, 0.5), size=(0.4, 0.4, 0.5), hist=hist_of({30: 500}), colour="brown")
    merge_local_graph(store, graph([table]))
    merge_local_graph(store, graph([chair]))
    assert sorted(o["label"] for o in objects(store)) == ["chair", "dining table"]


def test_a_view_linking_two_stored_parts_folds_them_into_one_node_with_their_edges(store):
    hist = hist_of({30: 500})
    left = obj("l", "dining table", (-1.0, 0.0, 1.0), size=(0.8, 0.8, 0.1), hist=hist, colour="brown")
    right = obj("r", "dining table", (1.0, 0.0, 1.0), size=(0.8, 0.8, 0.1), hist=hist, colour="brown")
    cup = obj("c", "cup", (1.0, 0.0, 1.1))
    chair = obj("h", "chair", (-1.0, 0.7, 0.5), hist=hist_of({200: 100}), colour="black")
    merge_local_graph(store, graph([left, chair], relations=[("h", "NEXT_TO", "l", 0.8)]))
    merge_local_graph(store, graph([right, cup], relations=[("c", "ON", "r", 0.9)]))
    assert sorted(o["label"] for o in objects(store)) == ["chair", "cup", "dining table", "dining table"]
    whole = obj("w", "dining table", (0.0, 0.0, 1.0), size=(2.4, 0.8, 0.1), hist=hist, colour="brown")
    report = merge_local_graph(store, graph([whole]))
    assert report.absorbed == 1
    nodes = objects(store)
    assert sorted(o["label"] for o in nodes) == ["chair", "cup", "dining table"]
    [table] = [o for o in nodes if o["label"] == "dining table"]
    assert table["observations"] == 3
    [chair_node] = [o for o in nodes if o["label"] == "chair"]
    rels = {(r["s"], r["type"], r["o"]) for r in store.read("relation_all", room=ROOM, types=list(RELATION_TYPES))}
    # NEXT_TO is symmetric: stored once, subject = the smaller global id
    lo, hi = sorted((chair_node["id"], table["id"]))
    assert {(t, o) for _, t, o in rels if t == "ON"} == {("ON", table["id"])}
    assert {r for r in rels if r[1] == "NEXT_TO"} == {(lo, "NEXT_TO", hi)}
