"""All or nothing (a real embedded store each): deleting a room and repairing the store are one
transaction each, so a kill between their statements leaves the store as it was; and `sg3d db
check` finds tallies that disagree with the objects, so the next repair fixes them.

The kill is injected at the boundary between sg3d and the store: a wrapper around the real
store whose transactions raise before their (n+1)-th statement, as a process killed there would
leave them (the store rolls back a transaction whose client went)."""
from __future__ import annotations

import pytest

from sg3d.app import rooms as rooms_app
from sg3d.app.check import check_store
from sg3d.graphdb import cypher
from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from sg3d.testing import KITCHEN_RELATIONS, graph, kitchen_objects, obj

KITCHEN = room_id("home", "kitchen")
OFFICE = room_id("home", "office")


class Killed(RuntimeError):
    """The process 'died' here: between two statements of a transaction."""


class _DyingTransaction:
    def __init__(self, tx, budget: list[int]):
        self._tx, self._budget = tx, budget

    def run(self, *args, **kwargs):
        if self._budget[0] <= 0:
            raise Killed("killed between two statements")
        self._budget[0] -= 1
        return self._tx.run(*args, **kwargs)

    def __getattr__(self, name):
        return getattr(self._tx, name)


class _DyingSession:
    def __init__(self, session, budget: list[int]):
        self._session, self._budget = session, budget

    def execute_write(self, fn, *args, **kwargs):
        return self._session.execute_write(lambda tx, *a, **kw: fn(_DyingTransaction(tx, self._budget), *a, **kw),
                                           *args, **kwargs)

    def __enter__(self):
        self._session.__enter__()
        return self

    def __exit__(self, *exc):
        return self._session.__exit__(*exc)

    def __getattr__(self, name):
        return getattr(self._session, name)


class DyingStore:
    """The real store; its writes die before the (n+1)-th write statement it sends (counted over
    every write transaction of this handle, so a delete of several transactions dies half done)."""

    def __init__(self, store, statements: int):
        self._store, self._budget = store, [statements]

    def session(self, **kw):
        return _DyingSession(self._store.session(**kw), self._budget)

    def execute_write(self, fn):
        with self.session() as s:
            return s.execute_write(fn)

    def write(self, name, **params):
        text = cypher.load(name)
        return self.execute_write(lambda tx: tx.run(text, params).data())

    def __getattr__(self, name):
        return getattr(self._store, name)


def count(store, text: str, **params) -> int:
    return store.run_raw(text, params)[1][0][0]


def snapshot(store) -> dict:
    """What the store holds, room by room and in all."""
    out = {label: count(store, f"MATCH (n:{label}) RETURN count(n)")
           for label in ("Object", "Appearance", "Tally", "MergeLog", "Scan", "Room")}
    out["edges"] = count(store, "MATCH ()-[e]->() RETURN count(e)")
    for rid in (KITCHEN, OFFICE):
        for label in ("Object", "Tally", "MergeLog", "Scan"):
            out[(rid, label)] = count(store, f"MATCH (n:{label}) WHERE n.room = $r RETURN count(n)", r=rid)
        out[(rid, "Room")] = count(store, "MATCH (r:Room {id: $r}) RETURN count(r)", r=rid)
    return out


def tallies(store) -> dict:
    rows = store.run_raw("MATCH (t:Tally) WHERE t.n <> 0 RETURN t.room, t.label, t.colour, t.n")[1]
    return {(r[0], r[1], r[2]): r[3] for r in rows}


CHUNKS = [graph(kitchen_objects()[:5], [r for r in KITCHEN_RELATIONS if r[0] in {"cupA", "cupB", "cupC", "bowl"}
                                         and r[2] in {"table", "bowl"}], key="seq:chunk-0"),
          graph(kitchen_objects()[5:], [("bottle", "IN", "micro", 0.8)], key="seq:chunk-1")]


def build(store) -> None:
    """Two keyed chunks in the kitchen (as `sg3d build` merges them) and an office of one."""
    for chunk in CHUNKS:
        assert not merge_local_graph(store, chunk).skipped
    merge_local_graph(store, graph([obj("d", "desk", (0.0, 0.0, 0.7), size=(1.2, 0.6, 0.7))], room="office",
                                   key="office:chunk-0"))


@pytest.fixture
def built(store, monkeypatch):
    monkeypatch.setattr(rooms_app, "DELETE_BATCH", 3)     # ten objects: four object statements
    build(store)
    return store


@pytest.mark.parametrize("statements", [1, 2, 3, 4, 5, 6, 7])
def test_a_delete_killed_between_statements_deletes_nothing(built, statements):
    """Four object batches, tallies, merge logs, scans, the room: killed before any of them, the
    kitchen is whole, the office untouched, and the room deletes and rebuilds afterwards."""
    before = snapshot(built)
    assert before[(KITCHEN, "Object")] == 10 and before[(KITCHEN, "MergeLog")] == 2 and before["edges"] > 0
    with pytest.raises(Killed):
        rooms_app.delete_room(DyingStore(built, statements), "home", "kitchen")
    assert snapshot(built) == before
    # the same delete, not killed: the whole room goes, the office stays
    done = rooms_app.delete_room(built, "home", "kitchen")
    assert done == {"room": KITCHEN, "objects": 10}
    after = snapshot(built)
    assert [after[(KITCHEN, k)] for k in ("Object", "Tally", "MergeLog", "Scan", "Room")] == [0] * 5
    assert all(after[(OFFICE, k)] == before[(OFFICE, k)] for k in ("Object", "Tally", "MergeLog", "Scan", "Room"))
    assert after["Appearance"] == after["Object"] == before[(OFFICE, "Object")]
    # the rebuild (the same chunk keys) merges again and restores the room
    for chunk in CHUNKS:
        assert not merge_local_graph(built, chunk).skipped
    assert snapshot(built) == before


def test_a_killed_delete_then_a_rebuild_gives_the_whole_room(built):
    """The audit's case: kill after the first object statement, then build the room again: every
    chunk is found merged and the room still holds every object (before: merged 0, 0 objects)."""
    before = snapshot(built)
    with pytest.raises(Killed):
        rooms_app.delete_room(DyingStore(built, 1), "home", "kitchen")
    assert all(merge_local_graph(built, chunk).skipped for chunk in CHUNKS)
    assert snapshot(built) == before
    assert count(built, "MATCH (o:Object) WHERE o.room = $r RETURN count(o)", r=KITCHEN) == 10


def stale(store):
    """A tally of 26 cups where the objects say 3 (as a repair killed before its recount left it)."""
    store.run_raw("MATCH (t:Tally) WHERE t.room = $r AND t.label = 'cup' AND t.colour = '' SET t.n = 26",
                  {"r": KITCHEN}, write=True)


def test_db_check_finds_tallies_that_disagree_with_the_objects_and_repair_fixes_them(built):
    good = tallies(built)
    assert check_store(built).clean
    stale(built)
    report = check_store(built)
    assert not report.clean and not report.objects and not report.rooms
    assert report.tallies == [{"room": KITCHEN, "label": "cup", "colour": "", "stored": 26, "counted": 3}]
    assert check_store(built, repair=True).repaired
    assert tallies(built) == good
    assert check_store(built).clean


def bad_object(store):
    """One kitchen object whose position is beyond the world extent (as `sg3d cypher --write` may store)."""
    store.run_raw("MATCH (o:Object) WHERE o.room = $r AND o.label = 'tv' SET o.x = 1.0e9", {"r": KITCHEN}, write=True)


@pytest.mark.parametrize("statements", [0, 1, 2, 3])
def test_a_repair_killed_before_its_recount_changes_nothing(built, statements):
    """The repair removes the bad object and recounts the tallies in one transaction: killed
    between them, the object and the tallies are as they were, and the next repair does it all."""
    good = tallies(built)
    bad_object(built)
    before = snapshot(built)
    with pytest.raises(Killed):
        check_store(DyingStore(built, statements), repair=True)
    assert snapshot(built) == before and tallies(built) == good
    report = check_store(built, repair=True)
    assert report.repaired and len(report.objects) == 1
    assert count(built, "MATCH (o:Object) WHERE o.room = $r RETURN count(o)", r=KITCHEN) == 9
    assert (KITCHEN, "tv", "") not in tallies(built)
    assert {k: v for k, v in good.items() if k[1] != "tv"} == tallies(built)
    assert check_store(built).clean
