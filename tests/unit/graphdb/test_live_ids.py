"""Which published node a live publish's row continues (sg3d/graphdb/live.py): `stable_ids`
within STABLE_ID_RADIUS_M, and `resumed_ids`, which gives a resumed map's rows the killed map's
ids before the ones this run made."""
from __future__ import annotations

from sg3d.graphdb.live import STABLE_ID_RADIUS_M, resumed_ids, stable_ids


def _node(gid: str, x: float, label: str = "chair") -> dict:
    return {"id": gid, "label": label, "layer": "object", "x": x, "y": 0.0, "z": 0.0}


def test_a_row_continues_the_nearest_node_of_its_label_within_the_radius():
    old = [_node("a", 0.0), _node("b", 1.0), _node("c", 0.1, label="cup")]
    assert stable_ids([_node("", 0.05)], old) == {0: "a"}
    assert stable_ids([_node("", STABLE_ID_RADIUS_M - 0.01)], old[:1]) == {0: "a"}
    assert stable_ids([_node("", STABLE_ID_RADIUS_M + 0.01)], old[:1]) == {}


def test_a_resumed_map_takes_back_the_killed_maps_id_before_its_own():
    killed, own = _node("killed", 0.3), _node("own", 0.02)    # this run's node lies nearer
    row = [_node("", 0.0)]
    assert stable_ids(row, [killed, own]) == {0: "own"}
    assert resumed_ids(row, [killed, own], frozenset({"killed"})) == {0: "killed"}


def test_without_unseen_nodes_it_is_stable_ids():
    old = [_node("a", 0.0), _node("b", 0.6)]
    rows = [_node("", 0.55), _node("", 0.1), _node("", 3.0)]
    assert resumed_ids(rows, old, frozenset()) == stable_ids(rows, old) == {0: "b", 1: "a"}


def test_rows_the_killed_map_left_unmatched_go_to_this_runs_nodes():
    old = [_node("killed", 0.0), _node("own", 2.0)]
    rows = [_node("", 2.1), _node("", 0.1)]
    assert resumed_ids(rows, old, frozenset({"killed"})) == {1: "killed", 0: "own"}
