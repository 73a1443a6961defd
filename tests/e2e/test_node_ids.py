"""The same frames give the same node ids: two builds of the same frames into two fresh stores
name every node alike and answer a list question alike; a second build into the same store
makes new ids that collide with none of the first's (the store's unique constraint would refuse
the merge). Real embedded stores, the real CLI, real kitchen frames."""
from __future__ import annotations

import json
from collections import Counter

import pytest

from sg3d.core.model import ScanInfo
from sg3d.graphdb.live import MAP_SCAN_PREFIX, publish
from sg3d.graphdb.merge import merge_local_graph
from sg3d.merge.similarity import SimilarityParams
from sg3d.testing import KITCHEN_RELATIONS, graph, kitchen_objects
from tests.cli_helpers import sg3d

LIST_QUESTION = "list the white objects"
# answers that named different neighbours in two builds while ids were random
TIE_QUESTIONS = ("where is the blue thing?", "what colour are the chairs?")
# every node kind a build writes, with its id (Appearance nodes carry their Object's id)
ALL_IDS = "MATCH (n) WHERE n.id IS NOT NULL RETURN labels(n) AS kind, n.id AS id ORDER BY id"
NO_MATCH = SimilarityParams(threshold=float("inf"))     # every observation a new node


def _ids(store) -> list[tuple[str, str]]:
    _, rows = store.run_raw(ALL_IDS)
    return sorted((",".join(sorted(kind)), i) for kind, i in rows)


def test_a_merge_names_its_nodes_alike_in_two_fresh_stores_and_anew_in_the_same(store):
    first = merge_local_graph(store, graph(kitchen_objects(), KITCHEN_RELATIONS))
    ids = _ids(store)
    store.wipe()
    store.ensure_schema()
    store.rooms_known.clear()
    again = merge_local_graph(store, graph(kitchen_objects(), KITCHEN_RELATIONS))
    assert again.node_ids == first.node_ids
    assert _ids(store) == ids
    # the same observations merged again into the same store, matching nothing: all new nodes
    second = merge_local_graph(store, graph(kitchen_objects(), KITCHEN_RELATIONS), params=NO_MATCH)
    assert second.created == len(kitchen_objects())
    assert not set(second.node_ids.values()) & set(first.node_ids.values())
    assert [k for k, n in Counter(_ids(store)).items() if n > 1] == []


def test_a_live_publish_names_its_nodes_alike_in_two_fresh_stores(store):
    def published() -> list[str]:
        publish(store, graph(kitchen_objects(), KITCHEN_RELATIONS), ScanInfo(f"{MAP_SCAN_PREFIX}home/kitchen@0", 0.0,
                                                                             closes=False), {"state": "live"})
        return sorted(r["o"]["id"] for r in store.read("object_all", room="home/kitchen"))

    ids = published()
    store.wipe()
    store.ensure_schema()
    store.rooms_known.clear()
    assert published() == ids


@pytest.fixture(scope="module")
def homes(tmp_path_factory):
    from sg3d.graphdb.embedded import EmbeddedServer

    made = [tmp_path_factory.mktemp("ids-a"), tmp_path_factory.mktemp("ids-b")]
    yield made
    for home in made:
        EmbeddedServer(home).stop()


def _build(home, kitchen_dir, *extra) -> dict:
    out = sg3d(home, "build", str(kitchen_dir), "--room", "kitchen", "--building", "ids",
               "--start", "0", "--stop", "120", "--json", *extra)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def _store_ids(home) -> list[tuple[str, str]]:
    out = sg3d(home, "cypher", ALL_IDS, "--json")
    assert out.returncode == 0, out.stderr
    return sorted((",".join(sorted(r["kind"])), r["id"]) for r in json.loads(out.stdout))


def _answer(home, question: str = LIST_QUESTION) -> dict:
    """The JSON answer to `question`, but the wall-clock times of the build (last_seen)."""
    out = sg3d(home, "ask", question, "--room", "kitchen", "--json")
    assert out.returncode == 0, out.stderr
    answer = json.loads(out.stdout)
    answer["provenance"] = [{k: v for k, v in p.items() if k != "last_seen"} for p in answer.get("provenance", [])]
    return answer


def test_two_builds_of_the_same_frames_give_the_same_ids_and_answers(homes, kitchen_dir):
    a, b = homes
    built = _build(a, kitchen_dir)
    assert built["graph"]["objects_created"] > 5
    assert _build(b, kitchen_dir)["graph"]["objects_created"] == built["graph"]["objects_created"]
    ids = _store_ids(a)
    assert sum(kind == "Object" for kind, _ in ids) == built["graph"]["room_objects"]
    assert _store_ids(b) == ids
    answer = _answer(a)
    assert answer["ok"] and len(answer["value"]) >= 2, answer["answer"]
    assert _answer(b) == answer
    for question in TIE_QUESTIONS:
        assert _answer(b, question) == _answer(a, question), question
    # the same frames again into the first store, as a build that matches nothing: new nodes only
    again = _build(a, kitchen_dir, "--method", "2d-basic")
    assert again["graph"]["objects_created"] > 5
    after = _store_ids(a)
    assert set(ids) <= set(after)
    assert [k for k, n in Counter(after).items() if n > 1] == []
    assert sum(kind == "Object" for kind, _ in after) == built["graph"]["room_objects"] + again["graph"]["objects_created"]
