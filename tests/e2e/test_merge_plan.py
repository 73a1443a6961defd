"""The merge's decisions without a store: hand-made local graphs against hand-made stored nodes
(the rows cypher/merge_candidates returns), planned by `sg3d.merge.plan.plan_merge`."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from sg3d.core.embedding import shipped_vectors
from sg3d.core.geometry import gravity_basis
from sg3d.core.model import ScanInfo
from sg3d.merge.ids import MergeIds
from sg3d.merge.plan import (
    _new_props,
    plan_merge,
    position_scores,
)
from sg3d.merge.similarity import SimilarityParams
from sg3d.merge.histograms import unpack_hist
from tests.factories import graph, hist_of, obj

ROOM = "home/kitchen"
EARLIER, NOW = ScanInfo("s1", 100.0), ScanInfo("s2", 200.0)
STORED = MergeIds(ROOM, 1)              # the merge that made the hand-made stored nodes
_made = itertools.count()


class ShippedVectors:
    """The shipped household vocabulary's MiniLM vectors: real label similarity, no model load."""

    name = "shipped-minilm"

    def __init__(self):
        self.table = shipped_vectors()

    def vectors(self, labels):
        return {label: self.table[label] for label in labels if label in self.table}


@pytest.fixture(scope="module")
def embedding():
    vectors = ShippedVectors()
    if not vectors.table:
        pytest.skip("the shipped label vectors (ingest/data) are absent")
    return vectors


def stored(observation, scan=EARLIER, **changes) -> dict:
    """A stored node as the merge reads it: the properties a merge created it with."""
    props = _new_props(observation, STORED.object_id(next(_made)), ROOM, scan.at, scan)
    return {**props, "removed_at": None, **changes}


def plan(local, nodes=(), moved_from=(), embedding=None, scan=NOW):
    nodes = list(nodes)
    params = SimilarityParams()
    s_pos = position_scores(local.objects, nodes, params, gravity_basis(local.up)) if nodes else None
    return plan_merge(local, nodes, s_pos, list(moved_from), embedding, scan, scan.at, MergeIds(ROOM, 2), params)


def test_an_empty_room_creates_every_object_and_counts_it(embedding):
    cup, table = obj("c", "cup", (1.0, 0.0, 1.1)), obj("t", "dining table", (1.0, 0.0, 0.8), size=(1.2, 0.8, 0.1))
    p = plan(graph([cup, table], relations=[("c", "ON", "t", 0.9)]), embedding=embedding)
    assert len(p.creates) == 2 and not p.updates and not p.folds and not p.cleared
    assert sorted(p.counted) == [("cup", "white"), ("dining table", "white")] and not p.uncounted
    ids = {row["props"]["id"] for row in p.creates}
    assert set(p.node_ids) == {"c", "t"} and set(p.node_ids.values()) == ids
    # histograms and thumbnails go to the Appearance node, not the Object's own properties
    assert all("hist" not in row["props"] and row["hist"] for row in p.creates)
    [(rel_type, [row])] = p.relations
    assert rel_type == "ON" and (row["s"], row["o"]) == (p.node_ids["c"], p.node_ids["t"])
    assert row["at"] == NOW.at and p.resolve


def test_a_second_view_of_a_cup_updates_its_node_with_the_papers_moments(embedding):
    first = obj("c1", "cup", (1.00, 0.50, 2.00), var=(0.01, 0.02, 0.03), n_points=100, hist=hist_of({7: 60}))
    node = stored(first)
    second = obj("c2", "cup", (1.04, 0.48, 2.03), var=(0.02, 0.01, 0.01), n_points=300, hist=hist_of({7: 50, 9: 30}))
    p = plan(graph([second]), [node], embedding=embedding)
    assert not p.creates and p.node_ids == {"c2": node["id"]}
    [row] = p.updates
    m1, m2 = np.array(first.mean), np.array(second.mean)
    assert np.allclose([row["props"][k] for k in "xyz"], (100 * m1 + 300 * m2) / 400)
    assert row["props"]["n_points"] == 400 and row["props"]["observations"] == 2
    assert np.allclose(unpack_hist(row["hist"]), hist_of({7: 110, 9: 30}))
    assert row["props"]["last_scan"] == NOW.id and row["props"]["scans"] == [EARLIER.id, NOW.id]
    # the node leaves the tallies under its old label and colour and enters under its new ones
    assert p.uncounted == [("cup", "white")] and p.counted == [("cup", "white")]


def test_a_sofa_where_a_mug_is_stored_is_a_new_node(embedding):
    mug = stored(obj("m", "mug", (0.0, 0.0, 1.0)))
    p = plan(graph([obj("s", "couch", (0.0, 0.0, 1.0), hist=hist_of({300: 100}), colour="red")]), [mug],
             embedding=embedding)
    assert not p.updates and len(p.creates) == 1 and p.node_ids["s"] != mug["id"]


def test_a_view_linking_two_stored_parts_folds_one_into_the_other(embedding):
    hist = hist_of({30: 500})
    left = stored(obj("l", "dining table", (-1.0, 0.0, 1.0), size=(0.8, 0.8, 0.1), hist=hist, colour="brown"))
    right = stored(obj("r", "dining table", (1.0, 0.0, 1.0), size=(0.8, 0.8, 0.1), hist=hist, colour="brown"))
    whole = obj("w", "dining table", (0.0, 0.0, 1.0), size=(2.4, 0.8, 0.1), hist=hist, colour="brown")
    p = plan(graph([whole]), [left, right], embedding=embedding)
    [(old, into)] = p.folds
    assert {old, into} == {left["id"], right["id"]} and p.absorbed == 1
    [row] = p.updates
    assert row["id"] == into and row["props"]["observations"] == 3
    # both stored nodes leave the tallies, the one they became enters them
    assert sorted(p.uncounted) == [("dining table", "brown")] * 2 and p.counted == [("dining table", "brown")]
    assert p.resolve     # folded edges may now contradict each other


def test_an_unmatched_view_of_a_vanished_mug_moves_it_and_keeps_its_old_place(embedding):
    hist = hist_of({40: 100})
    mug = stored(obj("m", "cup", (0.0, 0.0, 1.0), hist=hist, colour="red"))
    elsewhere = obj("n", "cup", (3.0, 2.0, 1.0), hist=hist, colour="red")
    local = graph([elsewhere])
    local.empty_places = {mug["id"]: [4, 5]}
    p = plan(local, [], moved_from=[mug], embedding=embedding)
    assert p.cleared == [mug["id"]] and not p.creates and p.node_ids == {"n": mug["id"]}
    [row] = p.updates
    assert (row["props"]["x"], row["props"]["y"]) == (3.0, 2.0)
    assert row["props"]["history_x"] == [0.0] and row["props"]["moved_scan"] == NOW.id
    # the node was seen again, so its place is not recorded as empty
    assert p.empty_places == []


def test_a_vanished_mug_that_nothing_resembles_keeps_its_place_seen_empty(embedding):
    mug = stored(obj("m", "cup", (0.0, 0.0, 1.0), hist=hist_of({40: 100}), colour="red"))
    local = graph([obj("b", "book", (3.0, 2.0, 1.0), hist=hist_of({300: 100}), colour="blue")])
    local.empty_places = {mug["id"]: [5, 4, 5]}
    p = plan(local, [], moved_from=[mug], embedding=embedding)
    assert not p.cleared and len(p.creates) == 1
    assert p.empty_places == [{"id": mug["id"], "frames": [4, 5]}]


def test_a_relation_to_an_object_the_graph_lacks_is_refused(embedding):
    with pytest.raises(KeyError):
        plan(graph([obj("a", "cup", (0.0, 0.0, 1.0))], relations=[("a", "ON", "missing", 0.9)]), embedding=embedding)


def test_an_unnamed_nodes_shape_follows_its_merged_box(embedding):
    """The stored shape class is the merged box's (sg3d.core.shape), not the first view's word:
    a slab seen flat, then with what stands on it, is no longer said to be flat."""
    first = obj("s", "object", (0.0, 0.0, 0.76), size=(0.45, 0.14, 0.02), colour="black", hist=hist_of({0: 100}))
    node = stored(first)
    assert node["shape"] == "flat"
    again = obj("s", "object", (0.0, 0.0, 0.90), size=(0.45, 0.14, 0.30), colour="black", hist=hist_of({0: 100}))
    p = plan(graph([again]), [node], embedding=embedding)
    [row] = p.updates
    assert row["props"]["size"][2] == pytest.approx(0.30)
    assert row["props"]["shape"] is None
    # a named node keeps no shape class
    cup = stored(obj("c", "cup", (2.0, 0.0, 0.8)))
    assert cup["shape"] is None
