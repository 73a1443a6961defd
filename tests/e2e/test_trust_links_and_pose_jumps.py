"""Trust, the rest of issue 38, on real data, real stores and a real server (no mocks):

- `sg3d rooms link` refuses an alignment without independent evidence (the 7-Scenes kitchen and the
  3DMatch study room share no object, only walls, a shelf level and blobs), says why in one line and
  takes --force; the living room and its pose-free copy still link; `rooms unlink` removes a link.
- a block of frames whose poses jump 50 m is skipped and named, and leaves no ghost objects;
- a failed ingest leaves no room behind; `/health` reports a full disk; a 20 MB thumbnail is 413/422;
  an MCP tool error from the store carries the store's one-line message;
- `sg3d db check` runs the store's own CHECK DATABASE and finds a store whose files vanished.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tests.cli_helpers import one_error_line, sg3d
from tests.conftest import SHARED

STUDY = SHARED / "data" / "3dmatch-studyroom" / "fragment-1"
LIVING = SHARED / "data" / "open3d-livingroom1-micro"


def _need(path: Path) -> Path:
    if not path.exists():
        pytest.skip(f"{path} is not there (set SG3D_SHARED)")
    return path


def _json(out) -> dict:
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def _rooms(home) -> dict:
    return {r["name"]: r for r in _json(sg3d(home, "rooms", "--json"))}


def _same_as(home) -> int:
    out = sg3d(home, "cypher", "MATCH (:Object)-[s:SAME_AS]->(:Object) RETURN count(s) AS n", "--json")
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)[0]["n"]


# -- rooms link: evidence, --force, unlink --------------------------------------------------------
@pytest.fixture(scope="module")
def four_rooms(tmp_path_factory, kitchen_dir):
    """The kitchen, the study room (fragment 1), the living room and the living room built again
    from its images alone (--estimate-poses: another world frame), each its own room."""
    from sg3d.graphdb.embedded import EmbeddedServer

    home = tmp_path_factory.mktemp("link-home")
    for room, path, extra in (("kitchen", kitchen_dir, ()), ("study", _need(STUDY), ()),
                              ("living", _need(LIVING), ()), ("livingest", LIVING, ("--estimate-poses",))):
        out = sg3d(home, "build", path, "--room", room, "--json", *extra)
        assert out.returncode == 0, out.stderr
    yield home
    EmbeddedServer(home).stop()


def test_linking_the_kitchen_and_the_study_room_is_refused_with_the_reason(four_rooms):
    """Refused either way the evidence falls short: no alignment at all from what the rooms share,
    or one resting on structure and blobs; the line says which, and nothing is stored."""
    before = _rooms(four_rooms)
    for a, b in (("kitchen", "study"), ("study", "kitchen")):
        line = one_error_line(sg3d(four_rooms, "rooms", "link", a, b))
        # an alignment too weak (the evidence rule, overridable) or none at all (RANSAC's reasons)
        assert ("refusing to link" in line and "agreeing in label, colour and size" in line and "--force" in line) \
            or any(why in line for why in ("3-object sample", "agree with any rigid transform", "match by label")), line
    # nothing was stored: no adjacency, no SAME_AS, no new transform
    assert _rooms(four_rooms) == before and _same_as(four_rooms) == 0
    assert not before["study"]["adjacent"] and before["study"]["to_building"] is None


def _structure_rooms(home) -> None:
    """Two hand-made rooms that share only three shelf levels of one colour (structure: every room
    has such), the second 5 m along x: an alignment exists, and no object backs it."""
    from dataclasses import replace

    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.merge import merge_local_graph
    from sg3d.graphdb.store import Store
    from sg3d.testing import graph, obj

    info = EmbeddedServer(home).ensure_running()
    store = Store(info.uri, (info.user, info.password), info.database)
    try:
        for room, dx in (("left", 0.0), ("right", 5.0)):
            levels = [replace(obj(f"s{k}", "shelf", (x + dx, y, z), size=(1.0, 0.4, 0.05), colour="white"),
                              layer="structure")
                      for k, (x, y, z) in enumerate(((0, 0, 0.8), (2, 0, 1.2), (0, 1.5, 1.6)))]
            merge_local_graph(store, graph(levels, room=room, building="default"))
    finally:
        store.close()


def test_force_links_a_weak_alignment_and_unlink_removes_it(four_rooms):
    _structure_rooms(four_rooms)
    line = one_error_line(sg3d(four_rooms, "rooms", "link", "left", "right"))
    assert "refusing to link" in line and "--force" in line
    out = sg3d(four_rooms, "rooms", "link", "left", "right", "--force", "--json")
    report = _json(out)
    assert report["forced"] and report["evidence"] < 3
    assert _rooms(four_rooms)["right"]["adjacent"] == ["left"] and _same_as(four_rooms) == report["same_as"]
    removed = _json(sg3d(four_rooms, "rooms", "unlink", "left", "right", "--json"))
    assert removed == {"room_a": "default/left", "room_b": "default/right", "adjacent": 2,
                       "same_as": report["same_as"]}
    rooms = _rooms(four_rooms)
    assert not rooms["right"]["adjacent"] and not rooms["left"]["adjacent"] and _same_as(four_rooms) == 0
    # nothing left to unlink: one line, exit 2
    assert "are not linked" in one_error_line(sg3d(four_rooms, "rooms", "unlink", "left", "right"))


def test_the_living_room_and_its_pose_free_copy_still_link(four_rooms):
    report = _json(sg3d(four_rooms, "rooms", "link", "living", "livingest", "--json"))
    assert report["forced"] is None and report["evidence"] >= 3 and report["share"] >= 0.5
    assert report["residual_rms_m"] < 0.05 and report["up_angle_deg"] < 2.0
    T = np.array(report["transform"])
    rooms = _rooms(four_rooms)
    assert rooms["livingest"]["adjacent"] == ["living"] and _same_as(four_rooms) == report["same_as"] >= 3
    # the copy's objects land on the living room's: the transform moves its centres onto them
    assert np.allclose(T[3], [0, 0, 0, 1])
    removed = _json(sg3d(four_rooms, "rooms", "unlink", "livingest", "living", "--json"))
    assert removed["adjacent"] == 2 and removed["same_as"] == report["same_as"]
    assert _same_as(four_rooms) == 0 and not _rooms(four_rooms)["living"]["adjacent"]


# -- pose continuity ------------------------------------------------------------------------------
def _shifted_kitchen(kitchen_dir: Path, root: Path, shifted=range(76, 84), metres=50.0) -> Path:
    """The kitchen's first 100 frames with the poses of `shifted` moved `metres` along x."""
    root.mkdir()
    (root / "camera-intrinsics.txt").symlink_to(kitchen_dir / "camera-intrinsics.txt")
    for i in range(100):
        for kind, ext in (("color", "jpg"), ("depth", "png")):
            (root / f"frame-{i:06d}.{kind}.{ext}").symlink_to(kitchen_dir / f"frame-{i:06d}.{kind}.{ext}")
        pose = np.loadtxt(kitchen_dir / f"frame-{i:06d}.pose.txt")
        if i in shifted:
            pose[0, 3] += metres
        np.savetxt(root / f"frame-{i:06d}.pose.txt", pose)
    return root


def test_a_block_of_frames_shifted_50_m_is_skipped_named_and_leaves_no_ghosts(kitchen_dir, tmp_path):
    from sg3d.graphdb.embedded import EmbeddedServer

    seq = _shifted_kitchen(kitchen_dir, tmp_path / "shifted")
    home = tmp_path / "home"
    try:
        summary = _json(sg3d(home, "build", seq, "--room", "kitchen", "--json"))
        exported = _json(sg3d(home, "export", "--room", "kitchen", "--out", "-"))
    finally:
        EmbeddedServer(home).stop()
    skipped = {s["frame"]: s["reason"] for s in summary["frames"]["skipped_frames"]}
    assert sorted(skipped) == [f"frame-{i:06d}" for i in range(76, 84)]
    assert all("jumps 50 m" in why and "from frame-000075" in why for why in skipped.values())
    assert summary["frames"]["read"] == 92
    # every object lies within the kitchen (the real camera never left a 5 m box): no ghost at 49 m
    centres = np.array([[o["x"], o["y"], o["z"]] for o in exported["nodes"]])
    assert len(centres) > 5
    assert np.abs(centres - np.median(centres, axis=0)).max() < 10.0


# -- a failed ingest leaves nothing behind --------------------------------------------------------
class StoreWhoseMergeFails:
    """The real store; the merge transaction of an ingest (its first statement is room_ensure)
    meets a real store error there ('/ by zero' from the store, as a full disk would fail it), so
    the store rolls that transaction back. Every other statement runs as it is."""

    def __init__(self, store):
        self._store, self.failed = store, 0

    def execute_write(self, fn):
        from sg3d.graphdb import cypher

        first = cypher.load("room_ensure")
        outer = self

        class Tx:
            def __init__(self, tx):
                self._tx = tx

            def run(self, text, *args, **kwargs):
                if text == first:
                    outer.failed += 1
                    return self._tx.run("RETURN 1 / 0 AS boom")
                return self._tx.run(text, *args, **kwargs)

            def __getattr__(self, name):
                return getattr(self._tx, name)

        return self._store.execute_write(lambda tx: fn(Tx(tx)))

    def __getattr__(self, name):
        return getattr(self._store, name)


def _count(store, text: str, **params) -> int:
    return store.run_raw(text, params)[1][0][0]


def test_a_failed_ingest_leaves_no_room_and_no_building_behind(store):
    from neo4j.exceptions import Neo4jError

    from sg3d.app.ingest import IngestRequest, ingest_graph
    from sg3d.testing import kitchen_body

    req = IngestRequest.model_validate(kitchen_body(building="annex", room="lab"))
    failing = StoreWhoseMergeFails(store)
    with pytest.raises(Neo4jError, match="ArithmeticError"):
        ingest_graph(failing, req)
    assert failing.failed == 1
    assert _count(store, "MATCH (r:Room {id: 'annex/lab'}) RETURN count(r)") == 0
    assert _count(store, "MATCH (b:Building {id: 'annex'}) RETURN count(b)") == 0
    assert _count(store, "MATCH (o:Object) WHERE o.room = 'annex/lab' RETURN count(o)") == 0
    # the next ingest of the same observation is a first one: it creates the room and merges
    done = ingest_graph(store, req)
    assert not done["skipped"] and done["room_objects"] == 10


def test_a_failed_ingest_into_a_room_that_was_there_keeps_the_room(store):
    from neo4j.exceptions import Neo4jError

    from sg3d.app.ingest import IngestRequest, ingest_graph
    from sg3d.testing import kitchen_body

    ingest_graph(store, IngestRequest.model_validate(kitchen_body()))
    before = _count(store, "MATCH (o:Object) WHERE o.room = 'home/kitchen' RETURN count(o)")
    with pytest.raises(Neo4jError):
        ingest_graph(StoreWhoseMergeFails(store), IngestRequest.model_validate(kitchen_body("obs-2")))
    assert _count(store, "MATCH (r:Room {id: 'home/kitchen'}) RETURN count(r)") == 1
    assert _count(store, "MATCH (o:Object) WHERE o.room = 'home/kitchen' RETURN count(o)") == before == 10


# -- the service: a full disk, a huge thumbnail, MCP errors, the store's own listener -------------
def test_health_reports_a_full_disk(served, monkeypatch):
    import httpx

    url, _ = served
    assert httpx.get(f"{url}/health", timeout=10).status_code == 200
    monkeypatch.setenv("SG3D_MIN_FREE_MB", str(10 ** 12))      # more than any disk has: it reads as full
    r = httpx.get(f"{url}/health", timeout=10)
    assert r.status_code == 507, r.text
    assert r.json()["state"] == "disk full" and "is full" in r.json()["status"]
    monkeypatch.setenv("SG3D_MIN_FREE_MB", "0")
    assert httpx.get(f"{url}/health", timeout=10).json()["state"] == "up"


def test_a_20_mb_thumbnail_is_refused_with_413_or_422_not_500(served, store):
    import base64

    import httpx

    from sg3d.testing import kitchen_body

    url, token = served
    body = kitchen_body(room="thumbs")
    body["graph"]["objects"][0]["thumbnail"] = base64.b64encode(b"\xff\xd8" + b"\0" * (20 * 1024 * 1024)).decode()
    r = httpx.post(f"{url}/ingest", json=body, headers={"Authorization": f"Bearer {token}"}, timeout=120)
    assert r.status_code in (413, 422), r.text[:300]
    assert len(r.content) < 4000                          # named, never echoed
    assert _count(store, "MATCH (r:Room {id: 'home/thumbs'}) RETURN count(r)") == 0


def test_an_mcp_tool_error_from_the_store_carries_the_stores_message(store, embedded_home):
    import anyio
    from mcp.server.mcpserver.exceptions import ToolError

    from sg3d.server.mcp import build_server
    from sg3d.settings import Settings

    server = build_server(Settings(home=embedded_home))
    # a DatabaseError of the store (not a ClientError, which the cypher tool names itself)
    with pytest.raises(ToolError) as caught:
        anyio.run(server.call_tool, "cypher", {"statement": "UNWIND range(1, 3) AS x RETURN x.foo AS y"})
    text = str(caught.value)
    assert "Cannot access property 'foo'" in text and "Neo.DatabaseError" in text, text
    assert "\n" not in text and len(text) < 400


def _listening_addresses(port: int) -> set[str]:
    """Local addresses with a listening TCP socket on `port` (/proc/net/tcp and tcp6)."""
    found = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in Path(table).read_text().splitlines()[1:]:
            local, state = line.split()[1], line.split()[3]
            address, hex_port = local.rsplit(":", 1)
            if state == "0A" and int(hex_port, 16) == port:      # 0A: LISTEN
                found.add(address)
    return found


def test_the_stores_own_http_listener_is_loopback_only_and_serves_no_studio(store, embedded_home):
    import httpx

    from sg3d.graphdb.embedded import EmbeddedServer

    info = EmbeddedServer(embedded_home).status().info
    assert info is not None
    # ArcadeDB cannot turn its HTTP API off (and `db check` needs it): it listens on loopback only
    # (127.0.0.1 in IPv4 or IPv4-mapped IPv6 form), on a random port, every call behind a password;
    # the wheel bundles no Studio (its root page says so) and the MCP endpoint is off
    loopback = {"0100007F", "0000000000000000FFFF00000100007F", "00000000000000000000000001000000"}
    addresses = _listening_addresses(info.http_port)
    assert addresses and addresses <= loopback, addresses
    assert info.http_port not in (2480, 2481) and info.bolt_port != 7687        # no well-known port
    root = httpx.get(f"http://127.0.0.1:{info.http_port}/", timeout=10)
    assert root.status_code == 404 or "not bundled" in root.text, root.text[:500]
    for path in ("/api/v1/server", "/api/v1/query/sg3d/sql/select%201", "/api/v1/mcp"):
        assert httpx.get(f"http://127.0.0.1:{info.http_port}{path}", timeout=10).status_code in (401, 403, 404)
    config = json.loads((EmbeddedServer(embedded_home).home / "databases" / "config" / "mcp-config.json").read_text())
    assert config["enabled"] is False


# -- the store's own integrity ---------------------------------------------------------------------


def test_db_check_finds_a_damaged_dictionary_and_a_truncated_bucket(own_store):
    home, server = own_store
    out = sg3d(home, "db", "check")
    assert out.returncode == 0 and "passed the store's CHECK DATABASE" in out.stdout, out.stdout + out.stderr
    files = server.database_dir
    dictionary = next(files.glob("dictionary.*.dict"))
    bucket = next(p for p in files.glob("Object_0.*.bucket"))
    kept = dictionary.read_bytes()
    server.stop()
    with open(dictionary, "r+b") as f:                 # 400 bytes of the property-name dictionary
        f.seek(100)
        f.write(b"\0" * 400)
    out = sg3d(home, "db", "check", "--json")
    assert out.returncode == 1, out.stdout + out.stderr
    report = json.loads(out.stdout)
    assert report["integrity"] == "damaged" and "10 of 10 Object records have no id" in report["damage"][0]
    server.stop()
    dictionary.write_bytes(kept)
    with open(bucket, "r+b") as f:                     # the Object records' first page, zeroed
        f.seek(0)
        f.write(b"\0" * 65536)
    out = sg3d(home, "db", "check")
    assert out.returncode == 1, out.stdout + out.stderr
    assert out.stdout.startswith("the store is damaged:")


def test_a_database_folder_that_vanishes_under_the_daemon_fails_the_next_write(own_store):
    import shutil
    import time

    home, server = own_store
    pid = server.status().info.pid
    shutil.rmtree(server.home / "databases")
    deadline = time.monotonic() + 10
    while server.status().running and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not server.status().running, "the daemon went on with its files gone"
    # the next write is refused (one line, exit 2), never acknowledged into deleted files
    out = sg3d(home, "cypher", "--write", "CREATE (p:Probe {n: 1}) RETURN p.n")
    line = one_error_line(out)
    assert "vanished while the store ran" in line and "sg3d db start" in line
    out = sg3d(home, "db", "check")
    assert out.returncode == 1 and "vanished" in out.stdout, out.stdout + out.stderr
    assert pid not in server.daemon_pids()
    # `sg3d db start` is the user's word: an empty store, said on stderr
    out = sg3d(home, "db", "start")
    assert out.returncode == 0 and "starting an empty store" in out.stderr
    assert sg3d(home, "db", "check").returncode == 0
