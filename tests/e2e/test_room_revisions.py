"""Per-room revisions on a real store: every write path that changes what an answer over a room
can read bumps that room's revision in its own transaction, and the answer cache of `sg3d serve`
keeps an answer over one room through writes to another."""
from __future__ import annotations

import time

import numpy as np
import pytest

from sg3d.app.answers import AnswerCache, ask_kept
from sg3d.graphdb.values import room_id
from sg3d.testing import graph, obj

KITCHEN, LIVING = room_id("home", "kitchen"), room_id("home", "living room")


def _revisions(store) -> dict:
    from sg3d.app.answers import store_revision

    return dict(store_revision(store).revisions)


def _merge(store, room: str, label: str = "bottle", x: float = 20.0):
    from sg3d.graphdb.merge import merge_local_graph

    return merge_local_graph(store, graph([obj("n", label, (x, 0.0, 0.0))], room=room, building="home"))


def _publish(store, room: str):
    from sg3d.core.model import ScanInfo
    from sg3d.graphdb.live import publish

    status = {"state": "live", "since": time.time(), "frames": 10, "source": "test"}
    return publish(store, graph([obj("a", "vase", (30, 0, 0.4))], room=room, building="home"),
                   ScanInfo("map:revisions", time.time(), closes=False), status)


def _link(store, a: str, b: str):
    from sg3d.graphdb.building import link_rooms

    return link_rooms(store, a, b, transform=np.eye(4))   # the red chairs of both rooms coincide


def _unlink(store, a: str, b: str):
    from sg3d.graphdb.building import unlink_rooms

    _link(store, a, b)
    before = _revisions(store)
    unlink_rooms(store, a, b)
    return before


def _transform(store, room: str):
    from sg3d.graphdb.building import set_room_transform

    set_room_transform(store, room, np.eye(4))


def _repair_up(store, room: str):
    from sg3d.app.check import repair_in_tx

    store.execute_write(lambda tx: repair_in_tx(tx, [], [room]))


def _tallies(store, _room: str):
    from sg3d.graphdb.tally import rebuild_tallies

    rebuild_tallies(store)


def _taxonomy(store, _room: str):
    from sg3d.queries.taxonomy import ensure_taxonomy

    assert ensure_taxonomy(store, force=True)


def _user_write(store, _room: str):
    store.run_raw("MATCH (o:Object {label: 'tv'}) SET o.note = 'moved'", write=True)


# write path -> what it does to `room`
ONE_ROOM = {"merge": lambda s, r: _merge(s, "living room"), "live publish": lambda s, r: _publish(s, "living room"),
            "placement in the building": _transform}
EVERY_ROOM = {"db rebuild-tallies": _tallies, "db check --repair (an up cleared, tallies recounted)": _repair_up,
              "taxonomy load": _taxonomy,
              "sg3d cypher --write": _user_write}


@pytest.mark.parametrize("path", sorted(ONE_ROOM))
def test_a_write_to_one_room_bumps_its_revision_and_no_others(house, store, path):
    before = _revisions(store)
    ONE_ROOM[path](store, LIVING)
    after = _revisions(store)
    assert after[LIVING][1] > before[LIVING][1], (path, before, after)
    assert after[KITCHEN] == before[KITCHEN], path


@pytest.mark.parametrize("path", sorted(EVERY_ROOM))
def test_a_write_whose_reach_is_the_store_bumps_every_room(house, store, path):
    before = _revisions(store)
    EVERY_ROOM[path](store, LIVING)
    after = _revisions(store)
    assert all(after[r][1] > before[r][1] for r in (KITCHEN, LIVING)), (path, before, after)


def test_linking_and_unlinking_two_rooms_bump_both(house, store):
    before = _revisions(store)
    _link(store, KITCHEN, LIVING)
    linked = _revisions(store)
    assert all(linked[r][1] > before[r][1] for r in (KITCHEN, LIVING)), (before, linked)
    before = _unlink(store, KITCHEN, LIVING)
    after = _revisions(store)
    assert all(after[r][1] > before[r][1] for r in (KITCHEN, LIVING)), (before, after)


def test_a_room_made_or_deleted_changes_the_room_list(house, store):
    from sg3d.app.answers import store_revision
    from sg3d.app.rooms import delete_room
    from sg3d.graphdb.merge import create_room

    listing = store_revision(store).listing
    create_room(store, "home", "hall")
    made = store_revision(store).listing
    assert made != listing and room_id("home", "hall") in dict(store_revision(store).revisions)
    delete_room(store, "home", "hall")
    assert store_revision(store).listing == listing


def test_a_cached_answer_over_one_room_outlives_writes_to_another_and_not_to_its_own(house, store):
    cache = AnswerCache()
    question = "how many chairs are there?"
    first, hit = ask_kept(store, cache, question, room="kitchen")
    assert not hit and first["value"] == 3
    assert ask_kept(store, cache, question, room="kitchen")[1]
    _merge(store, "living room", "chair")                        # a write to the other room
    again, hit = ask_kept(store, cache, question, room="kitchen")
    assert hit and again["value"] == 3
    _publish(store, "living room")
    assert ask_kept(store, cache, question, room="kitchen")[1]
    _merge(store, "kitchen", "chair")                            # a write to the room it read
    fresh, hit = ask_kept(store, cache, question, room="kitchen")
    assert not hit and fresh["value"] == 4
    # an answer over every room is retired by a write to any of them
    assert not ask_kept(store, cache, question)[1]
    assert ask_kept(store, cache, question)[1]
    _merge(store, "living room", "bottle", x=25.0)
    assert not ask_kept(store, cache, question)[1]


ROOM_LIST_PARAMS = [
    ("vqa_room_named", {"names": ["kitchen", "Kitchen", "KITCHEN"], "building": None}),
    ("vqa_room_named", {"names": ["kitchen"], "building": "home"}),
    ("vqa_room_named", {"names": ["Kitchen"], "building": "barn"}),
    ("vqa_room_named", {"names": ["hall"], "building": None}),
    ("vqa_rooms", {"room": "kitchen", "building": None}),
    ("vqa_rooms", {"room": None, "building": "barn"}),
    ("vqa_rooms", {"room": None, "building": None}),
    ("vqa_rooms", {"room": "living room", "building": "home"}),
    ("vqa_room_names", {"building": None}),
    ("vqa_room_names", {"building": "barn"}),
]


@pytest.mark.parametrize("name,params", ROOM_LIST_PARAMS, ids=[f"{n}-{i}" for i, (n, _) in enumerate(ROOM_LIST_PARAMS)])
def test_a_room_list_read_answered_from_the_revision_read_equals_the_store_s(house, store, name, params):
    from sg3d.app.answers import room_list_rows, store_revision
    from sg3d.graphdb.merge import create_room

    create_room(store, "Barn", "Kitchen")           # another case, another building
    create_room(store, "barn", "loft")
    assert room_list_rows(name, params, store_revision(store).listing) == store.read(name, **params)


def test_an_answer_reads_in_one_transaction_and_answers_as_one_per_read(house, store, monkeypatch):
    """`ask` sends every read of an answer in one read transaction (`Store.reading`): one
    transaction function of the driver per answer, and the same answer as with one transaction per read."""
    from neo4j import Session

    from sg3d.app.ask import ask

    class EachRead:                  # the store, every read in its own transaction
        def __init__(self, s):
            self._s = s

        def reading(self, fn):
            return fn()

        def __getattr__(self, name):
            return getattr(self._s, name)

    transactions = []
    real = Session.execute_read
    monkeypatch.setattr(Session, "execute_read", lambda self, fn, *a, **kw: transactions.append(1) or real(
        self, fn, *a, **kw))
    for question in ("what is on the table?", "how many chairs are there?", "where is the red chair?"):
        transactions.clear()
        one = ask(store, question, room="kitchen").to_json()
        assert len(transactions) == 1, (question, len(transactions))
        transactions.clear()
        each = ask(EachRead(store), question, room="kitchen").to_json()
        assert len(transactions) > 1, question
        assert one == each, question
