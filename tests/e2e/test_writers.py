"""One writer per room (`sg3d.graphdb.lease`, `sg3d.app.writers`) and a live publish that removes only
what a map made, with a real embedded store: leases refused, waited for and taken over from dead
holders; an ingest refused with 409 while a build holds the room; a build's objects untouched by a
map's publish; a resumed map keeping the ids of what it has not yet seen again; a failed ingest
leaving no room; a build refusing a full disk before each merge."""
from __future__ import annotations

import json
import subprocess
import sys
import time

import pytest

from tests.cli_helpers import one_error_line, sg3d


def _objects(store, room: str, building: str = "default") -> list[dict]:
    return [row["o"] for row in store.read("export_objects", building=building, room=room)]


def _count(store, text: str, **params) -> int:
    return store.run_raw(text, params)[1][0][0]


# -- the lease --------------------------------------------------------------------------------------
def test_a_second_writer_is_refused_naming_the_holder_and_gets_the_room_once_it_is_released(store):
    from sg3d.graphdb.lease import LeaseHeld, RoomLease

    first = RoomLease(store, "home", "lab", "build", "sg3d build /data/kitchen")
    first.take()
    second = RoomLease(store, "home", "lab", "map", "sg3d map /data/live")
    with pytest.raises(LeaseHeld) as refused:
        second.take()
    line = str(refused.value)
    assert "\n" not in line and "build 'sg3d build /data/kitchen'" in line and "pid" in line
    assert RoomLease(store, "home", "other", "map", "m").try_take() is None     # another room is free
    first.release()
    second.take()
    second.release()


def test_a_lease_whose_holder_died_or_expired_is_taken_over(store):
    from sg3d.graphdb.lease import RoomLease

    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    gone = RoomLease(store, "home", "lab", "build", "killed build")
    gone.pid = dead.pid                     # as a build killed with kill -9 leaves it
    gone.take()
    gone._stop.set()
    assert RoomLease(store, "home", "lab", "map", "next").try_take() is None
    stale = RoomLease(store, "home", "hall", "build", "far away", ttl=0.2)
    stale.host = "another-host"             # its pid cannot be looked at: only the expiry tells
    stale.take()
    stale._stop.set()
    assert RoomLease(store, "home", "hall", "map", "next").try_take() is not None
    time.sleep(0.3)
    assert RoomLease(store, "home", "hall", "map", "next").try_take() is None


def test_a_writer_that_lost_its_lease_writes_nothing(store):
    from sg3d.graphdb.lease import LeaseLost, RoomLease
    from sg3d.graphdb.merge import merge_local_graph
    from sg3d.testing import graph, obj

    lease = RoomLease(store, "home", "lab", "build", "slow build", ttl=0.2)
    lease.take()
    lease._stop.set()                       # it stops renewing (a paused process)
    time.sleep(0.3)
    RoomLease(store, "home", "lab", "map", "next").take()
    with pytest.raises(LeaseLost, match="lost the lease"):
        merge_local_graph(store, graph([obj("a", "cup", (0, 0, 0))], room="lab"), fence=lease.fence)
    assert _count(store, "MATCH (o:Object) WHERE o.room = 'home/lab' RETURN count(o)") == 0


def test_an_ingest_waits_for_another_ingest_and_is_refused_while_a_build_writes(store):
    from sg3d.app.errors import RoomBusy
    from sg3d.app.ingest import IngestRequest, ingest_graph
    from sg3d.graphdb.lease import RoomLease
    from sg3d.testing import kitchen_body

    other = RoomLease(store, "home", "kitchen", "ingest", "POST /ingest obs-0")
    other.take()
    t0 = time.monotonic()
    import threading

    threading.Timer(0.5, other.release).start()
    done = ingest_graph(store, IngestRequest.model_validate(kitchen_body()))
    assert done["created"] == 10 and time.monotonic() - t0 >= 0.4
    build = RoomLease(store, "home", "kitchen", "build", "sg3d build /data/kitchen")
    build.take()
    try:
        with pytest.raises(RoomBusy, match="build 'sg3d build /data/kitchen'"):
            ingest_graph(store, IngestRequest.model_validate(kitchen_body("obs-2")))
    finally:
        build.release()
    assert ingest_graph(store, IngestRequest.model_validate(kitchen_body("obs-2")))["skipped"] is False


def test_ingest_over_http_is_409_while_a_build_holds_the_room(served, store):
    import httpx

    from sg3d.graphdb.lease import RoomLease
    from sg3d.testing import kitchen_body

    url, token = served
    build = RoomLease(store, "home", "kitchen", "build", "sg3d build /data/kitchen")
    build.take()
    try:
        r = httpx.post(f"{url}/ingest", json=kitchen_body(), headers={"Authorization": f"Bearer {token}"}, timeout=30)
    finally:
        build.release()
    assert r.status_code == 409, r.text
    assert "being written by build" in r.json()["detail"]
    r = httpx.post(f"{url}/ingest", json=kitchen_body(), headers={"Authorization": f"Bearer {token}"}, timeout=30)
    assert r.status_code == 200, r.text


# -- a publish removes only what a map made ------------------------------------------------------
def _status(frames: int = 10) -> dict:
    return {"state": "live", "since": time.time(), "frames": frames, "source": "test"}


def test_a_publish_leaves_a_builds_objects_relations_and_tallies(store):
    from sg3d.core.model import ScanInfo
    from sg3d.graphdb.live import publish
    from sg3d.graphdb.merge import merge_local_graph
    from sg3d.graphdb.tally import rebuild_tallies
    from sg3d.testing import graph, obj

    built = merge_local_graph(store, graph([obj("t", "dining table", (3, 0, 0.4), size=(1, 1, 0.8)),
                                            obj("c", "cup", (3, 0, 0.85))], [("c", "ON", "t", 0.9)],
                                           room="r", building="default", key="build:x:0-10"))
    assert built.created == 2
    scan = ScanInfo("map:default/r@1", time.time(), closes=False)
    publish(store, graph([obj("a", "chair", (0, 0, 0.4), size=(0.5, 0.5, 0.9))], room="r", building="default"),
            scan, _status())
    publish(store, graph([obj("b", "bottle", (1, 0, 0.8))], room="r", building="default"), scan, _status(20))
    labels = sorted(o["label"] for o in _objects(store, "r"))
    assert labels == ["bottle", "cup", "dining table"]          # the chair was the map's, the rest the build's
    assert _count(store, "MATCH (:Object {room: 'default/r'})-[e:ON]->(:Object) RETURN count(e)") == 1
    before = {(r["label"], r["colour"]): r["n"] for r in store.read("tally_all") if r["room"] == "default/r"}
    rebuild_tallies(store)
    after = {(r["label"], r["colour"]): r["n"] for r in store.read("tally_all") if r["room"] == "default/r"}
    assert before == after and after[("cup", "")] == 1


def test_a_resumed_maps_publish_keeps_what_it_has_not_seen_again_and_its_ids(store):
    from sg3d.core.model import ScanInfo
    from sg3d.graphdb.live import map_object_ids, publish
    from sg3d.testing import graph, obj

    def room(*objs):
        return graph(list(objs), room="r", building="default")

    chair, cup, sofa = (obj("a", "chair", (0, 0, 0.4), size=(0.5, 0.5, 0.9)), obj("b", "cup", (1, 0, 0.8)),
                        obj("c", "couch", (3, 0, 0.4), size=(2, 1, 0.8)))
    publish(store, room(chair, cup, sofa), ScanInfo("map:default/r@1", time.time(), closes=False), _status())
    ids = {o["label"]: o["id"] for o in _objects(store, "r")}
    unseen = map_object_ids(store, "default", "r")
    resumed = ScanInfo("map:default/r@2", time.time(), closes=False)
    # the resumed map's first publish saw only the newest frames: the cup
    r1 = publish(store, room(obj("b", "cup", (1.02, 0, 0.8))), resumed, _status(30), unseen=unseen)
    assert r1.removed == 0 and {o["label"]: o["id"] for o in _objects(store, "r")} == ids
    # the end (every frame seen): chair and cup found again keep their ids, the couch is gone
    r2 = publish(store, room(obj("a", "chair", (0.05, 0, 0.4), size=(0.5, 0.5, 0.9)), obj("b", "cup", (1.0, 0, 0.8))),
                 resumed, _status(40))
    assert (r2.kept, r2.removed, r2.created) == (2, 1, 0)
    assert {o["label"]: o["id"] for o in _objects(store, "r")} == {"chair": ids["chair"], "cup": ids["cup"]}


# -- a failed ingest leaves no room; a build refuses a full disk ---------------------------------
class StoreOnAFullDisk:
    """The real store on a disk that fills up: small transactions before the ingest's merge pass,
    the merge transaction (its room lock, room_ensure) meets a real store error, and from then on
    every write does (a clean-up after the failure cannot run either)."""

    def __init__(self, store):
        self._store, self.full = store, False

    def execute_write(self, fn):
        from sg3d.graphdb import cypher

        lock = cypher.load("room_ensure")
        outer = self

        class Tx:
            def __init__(self, tx):
                self._tx = tx

            def run(self, text, *args, **kwargs):
                if outer.full or text == lock:
                    outer.full = True
                    return self._tx.run("RETURN 1 / 0 AS boom")
                return self._tx.run(text, *args, **kwargs)

            def __getattr__(self, name):
                return getattr(self._tx, name)

        return self._store.execute_write(lambda tx: fn(Tx(tx)))

    def write(self, name, **params):
        if self.full:
            return self.execute_write(lambda tx: tx.run("RETURN 1").consume())
        return self._store.write(name, **params)

    def __getattr__(self, name):
        return getattr(self._store, name)


def test_a_failed_ingest_leaves_no_room_even_when_the_clean_up_fails_too(store):
    from neo4j.exceptions import Neo4jError

    from sg3d.app.ingest import IngestRequest, ingest_graph
    from sg3d.testing import kitchen_body

    req = IngestRequest.model_validate(kitchen_body(building="annex", room="lab"))
    with pytest.raises(Neo4jError):
        ingest_graph(StoreOnAFullDisk(store), req)
    assert _count(store, "MATCH (r:Room {id: 'annex/lab'}) RETURN count(r)") == 0
    assert _count(store, "MATCH (b:Building {id: 'annex'}) RETURN count(b)") == 0
    assert ingest_graph(store, req)["room_objects"] == 10


def test_a_build_refuses_a_disk_below_the_minimum_before_it_merges(store, embedded_home, kitchen_dir):
    out = sg3d(embedded_home, "build", kitchen_dir, "--room", "full", "--start", "0", "--stop", "40",
               SG3D_MIN_FREE_MB=str(10 ** 12))
    line = one_error_line(out)
    assert "is full" in line and "0 chunks were merged" in line
    assert _count(store, "MATCH (o:Object) WHERE o.room = 'default/full' RETURN count(o)") == 0


def test_a_build_whose_objects_were_deleted_merges_again_and_says_so(store, embedded_home, kitchen_dir):
    args = ("build", kitchen_dir, "--room", "gone", "--start", "0", "--stop", "40", "--json")
    first = sg3d(embedded_home, *args)
    assert first.returncode == 0, first.stderr
    made = json.loads(first.stdout)["graph"]["objects_created"]
    assert made > 0
    store.run_raw("MATCH (o:Object) WHERE o.room = 'default/gone' DETACH DELETE o", write=True)
    again = sg3d(embedded_home, *args)
    assert again.returncode == 0, again.stderr
    summary = json.loads(again.stdout)
    assert summary["graph"]["objects_created"] == made and summary["graph"]["remerged_chunks"] == 1
    assert "merging every chunk again" in again.stderr
