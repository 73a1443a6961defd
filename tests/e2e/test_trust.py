"""What a caller cannot do to the store through sg3d: smuggle Bolt messages past ArcadeDB's 16 MiB
message limit, hang the service with an oversize field, or make it wait on a dead or frozen store.
A real embedded store through the real driver, a real server through a real HTTP client."""
from __future__ import annotations

import base64
import json
import os
import signal
import struct
import subprocess
import sys
import threading
import time

import cv2
import httpx
import numpy as np
import pytest

from tests.serve_helpers import kitchen_body, running_server, serve_process

MIB = 1024 * 1024
STORE_LIMIT = 16 * MIB          # what ArcadeDB's Bolt plugin reads of one message
KITCHEN = "home/kitchen"
DELETE_KITCHEN = f"MATCH (o:Object {{room:'{KITCHEN}'}}) DETACH DELETE o"
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# -- helpers -------------------------------------------------------------------------------------
def _string(text: str) -> bytes:
    data = text.encode()
    if len(data) < 16:
        return bytes([0x80 + len(data)]) + data
    if len(data) < 256:
        return b"\xd0" + bytes([len(data)]) + data
    return b"\xd1" + struct.pack(">H", len(data)) + data


def _chunked(message: bytes) -> bytes:
    return struct.pack(">H", len(message)) + message + b"\x00\x00"


def bolt_messages(statement: str) -> bytes:
    """RESET, RUN `statement` and PULL all, as chunked Bolt messages (PackStream structures)."""
    reset = b"\xb0\x0f"
    run = b"\xb3\x10" + _string(statement) + b"\xa0" + b"\xa0"
    pull = b"\xb1\x3f" + b"\xa1" + _string("n") + b"\xff"         # {n: -1}
    return _chunked(reset) + _chunked(run) + _chunked(pull)


def smuggling_payload(statement: str) -> bytes:
    """What the finding sent: a JPEG start, more than 16 MiB of padding, then Bolt messages."""
    return b"\xff\xd8\xff\xe0" + b"\x00" * (STORE_LIMIT + 64 * 1024) + bolt_messages(statement) * 4


def within(seconds: float, fn):
    """`fn()`'s result or exception, failing the test if it has not returned within `seconds`
    (a call that sends an oversize message hangs in the driver: that must fail, not hang)."""
    out: dict = {}

    def run():
        try:
            out["value"] = fn()
        except BaseException as exc:  # noqa: BLE001 - handed to the test
            out["error"] = exc
    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(seconds)
    assert not worker.is_alive(), f"the call did not return within {seconds} s"
    return out


def n_objects(store, room: str) -> int:
    return store.read("object_count", room=room)[0]["n"]


def real_jpeg(side: int = 330, seed: int = 0) -> bytes:
    noise = np.random.default_rng(seed).integers(0, 256, (side, side, 3), dtype=np.uint8)
    ok, buf = cv2.imencode(".jpg", noise, [cv2.IMWRITE_JPEG_QUALITY, 100])
    assert ok
    return buf.tobytes()


@pytest.fixture
def client(kitchen_client):
    return kitchen_client


# -- finding 1: the crafted thumbnail ------------------------------------------------------------
def test_a_thumbnail_smuggling_bolt_messages_is_422_and_the_other_room_keeps_its_objects(client, store):
    assert n_objects(store, KITCHEN) == 10
    body = kitchen_body("smuggle", room="pantry")
    body["graph"]["objects"][0]["thumbnail"] = base64.b64encode(smuggling_payload(DELETE_KITCHEN)).decode()
    text = json.dumps(body)
    assert STORE_LIMIT < len(text) < 32 * MIB       # a valid /ingest body within --max-body
    t0 = time.monotonic()
    r = client.post("/ingest", content=text, headers={"content-type": "application/json"})
    assert r.status_code == 422, r.text[:300]
    assert time.monotonic() - t0 < 30
    detail = r.json()["detail"]
    assert any("thumbnail" in d["loc"] for d in detail), detail
    assert len(r.content) < 2000, "the error must not echo the thumbnail"
    assert n_objects(store, KITCHEN) == 10
    assert n_objects(store, "home/pantry") == 0
    assert client.get("/rooms/home/kitchen/objects").status_code == 200


def test_the_merge_itself_refuses_the_smuggling_thumbnail_and_writes_nothing(store):
    """Below the HTTP schema: a local graph handed straight to the merge (as a build, an import
    or a future door would) is refused by the store's guard before anything is sent."""
    from sg3d.graphdb.merge import merge_local_graph
    from sg3d.graphdb.store import StatementTooLarge
    from sg3d.testing import graph, kitchen_objects, obj

    merge_local_graph(store, graph(kitchen_objects(), key="k-1"))
    assert n_objects(store, KITCHEN) == 10
    bad = graph([obj("cup", "cup", (0.0, 0.0, 1.0), thumbnail=smuggling_payload(DELETE_KITCHEN))],
                room="pantry", key="smuggle")
    out = within(60, lambda: merge_local_graph(store, bad))
    assert isinstance(out.get("error"), StatementTooLarge), out
    assert "nothing was sent" in str(out["error"]) and len(str(out["error"]).splitlines()) == 1
    assert n_objects(store, KITCHEN) == 10 and n_objects(store, "home/pantry") == 0
    assert store.read("merge_log_exists", key="smuggle") == []


def test_an_oversize_statement_is_refused_before_anything_is_sent(store):
    """17 MiB of parameter whose tail is a RUN of CREATE: without the guard the store would run
    that CREATE (and the driver would hang); with it nothing leaves sg3d."""
    from sg3d.graphdb.store import MAX_STATEMENT_BYTES, StatementTooLarge

    payload = "x" * (17 * MIB) + bolt_messages("CREATE (:TrustProbe {n: 1})").decode("latin-1")
    t0 = time.monotonic()
    out = within(30, lambda: store.run_raw("RETURN size($x) AS n", {"x": payload}, write=True))
    assert isinstance(out.get("error"), StatementTooLarge), out
    assert time.monotonic() - t0 < 5
    assert "$x" in str(out["error"]) and "nothing was sent" in str(out["error"])
    assert store.run_raw("MATCH (p:TrustProbe) RETURN count(p)")[1] == [[0]]
    # the same connection still works, and a statement just under the bound goes through whole
    fits = "y" * (MAX_STATEMENT_BYTES - 1024)
    assert within(60, lambda: store.run_raw("RETURN size($x) AS n", {"x": fits}))["value"][1] == [[len(fits)]]


def test_a_merge_larger_than_one_message_is_split_into_batches_not_refused(client, store):
    """45 objects with real ~220 KB JPEG thumbnails: ~10 MB of new objects, more than one message
    may carry, merge in one transaction through /ingest, every thumbnail intact."""
    from sg3d.app.ingest import MAX_THUMBNAIL_BYTES
    from sg3d.graphdb.store import MAX_STATEMENT_BYTES

    body = kitchen_body("big", room="pantry")
    template = body["graph"]["objects"][1]
    pictures, objects = {}, []
    for i in range(45):
        pictures[f"c{i}"] = real_jpeg(seed=i)
        objects.append({**template, "id": f"c{i}", "mean": [0.5 * i, 0.0, 1.0],
                        "thumbnail": base64.b64encode(pictures[f"c{i}"]).decode()})
    assert all(150_000 < len(p) <= MAX_THUMBNAIL_BYTES for p in pictures.values())
    assert sum(map(len, pictures.values())) > MAX_STATEMENT_BYTES
    body["graph"].update(objects=objects, relations=[])
    r = client.post("/ingest", json=body, timeout=300)
    assert r.status_code == 200, r.text[:300]
    assert r.json()["created"] == 45 and n_objects(store, "home/pantry") == 45
    ids = r.json()["node_ids"]
    g = client.get("/graph", params={"building": "home", "room": "pantry", "thumbnails": "true"}).json()
    stored = {n["id"]: base64.b64decode(n["thumbnail_jpeg_base64"]) for n in g["nodes"]}
    assert all(stored[ids[local]] == picture for local, picture in pictures.items())
    assert n_objects(store, KITCHEN) == 10


# -- finding 2: an oversize field ----------------------------------------------------------------
def test_ask_with_a_six_million_character_room_is_a_quick_422_without_echo(client, served):
    url, _ = served
    t0 = time.monotonic()
    r = client.post("/ask", json={"question": "how many cups", "room": "k" * 6_000_000})
    took = time.monotonic() - t0
    assert r.status_code == 422, r.text[:300]
    assert took < 3, took
    assert len(r.content) < 1000 and "kkkk" not in r.text
    detail = r.json()["detail"]
    assert detail[0]["loc"] == ["body", "room"] and "6000000" in detail[0]["msg"], detail
    t1 = time.monotonic()
    health = httpx.get(url + "/health", timeout=5)
    assert health.status_code == 200 and health.json()["state"] == "up"
    assert time.monotonic() - t1 < 1
    r = client.post("/ask", json={"question": "how many cups are there?", "room": "kitchen"})
    assert r.status_code == 200 and r.json()["value"] == 3


@pytest.mark.parametrize("field", ["building", "question"])
def test_every_ask_field_is_bounded(client, field):
    body = {"question": "how many cups", field: "b" * 1_000_000}
    r = client.post("/ask", json=body)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", field]
    assert "1000000" in r.text and len(r.content) < 1000


def test_sigterm_stops_sg3d_serve_after_an_oversize_request(embedded_home, store_session):
    """The real console command: the oversize /ask is refused, /health still answers, SIGTERM ends it."""
    from sg3d.graphdb.embedded import free_port

    port = free_port()
    env = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(embedded_home), "serve", "--port", str(port)],
                            stderr=subprocess.PIPE, text=True, env=env)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 90
        while True:
            try:
                if httpx.get(base + "/health").status_code == 200:
                    break
            except httpx.TransportError:
                pass
            assert proc.poll() is None and time.monotonic() < deadline, "sg3d serve did not start"
            time.sleep(0.2)
        token = (embedded_home / "api-token").read_text().strip()
        r = httpx.post(base + "/ask", json={"question": "how many cups", "room": "k" * 6_000_000},
                       headers={"Authorization": f"Bearer {token}"}, timeout=30)
        assert r.status_code == 422
        assert httpx.get(base + "/health", timeout=5).status_code == 200
        t0 = time.monotonic()
        proc.send_signal(signal.SIGTERM)
        proc.wait(15)
        assert time.monotonic() - t0 < 15
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


# -- finding 3: a dead or frozen store -----------------------------------------------------------
QUICK_S = 3.0                     # the read deadline of the server over a store of its own
QUESTION = {"question": "how many cups are there?"}


@pytest.fixture
def own_store(tmp_path):
    """A store daemon of its own (it is killed or frozen here) and a server over it: (daemon, url, client)."""
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    home = tmp_path / "home"
    daemon = EmbeddedServer(home)
    daemon.ensure_running()
    token = ensure_token(home)
    try:
        with running_server(Settings(home=home), token, quick_timeout_s=QUICK_S) as url:
            with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120) as c:
                assert c.post("/ingest", json=kitchen_body()).status_code == 200
                _until_answered(c)
                yield daemon, url, c
    finally:
        daemon.stop()


def _until_answered(c, question=QUESTION, seconds: float = 120):
    """The answer to `question`, asked until it comes: the first reads of a new server (the label
    model loads) or of a restarted store may pass the short deadline these tests set."""
    deadline = time.monotonic() + seconds
    while True:
        r = c.post("/ask", json=question)
        if r.status_code == 200:
            return r
        assert r.status_code == 503 and time.monotonic() < deadline, r.text
        time.sleep(0.5)


def _daemon_pid(daemon) -> int:
    return json.loads(daemon.info_path.read_text())["pid"]


@pytest.fixture(params=["in-process", "serve --workers 2"])
def killable_store(request, tmp_path):
    """A store daemon of its own (it is killed here) and a server over it, the application in this
    process or the console command with two worker processes: (daemon, url, client)."""
    if request.param == "in-process":
        yield request.getfixturevalue("own_store")
        return
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.server.auth import ensure_token

    home = tmp_path / "home"
    daemon = EmbeddedServer(home)
    daemon.ensure_running()
    token = ensure_token(home)
    try:
        with serve_process(home, "--workers", "2") as url:
            with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120) as c:
                assert c.post("/ingest", json=kitchen_body()).status_code == 200
                for _ in range(4):           # each worker has answered (and loaded its label model)
                    _until_answered(c)
                yield daemon, url, c
    finally:
        daemon.stop()


def test_a_killed_store_is_503_with_retry_after_within_1_s_and_comes_back(killable_store):
    daemon, url, c = killable_store
    before = _until_answered(c).json()["answer"]
    os.kill(_daemon_pid(daemon), signal.SIGKILL)
    for request in (lambda: httpx.get(url + "/health", timeout=10), lambda: c.post("/ask", json=QUESTION)):
        t0 = time.monotonic()
        r = request()
        assert time.monotonic() - t0 < 1, (r.status_code, time.monotonic() - t0)
        assert r.status_code == 503 and int(r.headers["Retry-After"]) > 0, r.text
    health = httpx.get(url + "/health", timeout=10)
    assert health.json()["store"] is False and health.json()["state"] == "down"
    deadline = time.monotonic() + 120           # the service restarts the daemon in the background
    while httpx.get(url + "/health", timeout=10).status_code != 200:
        assert time.monotonic() < deadline, "the store did not come back"
        time.sleep(0.5)
    assert _until_answered(c).json()["answer"] == before


def test_a_frozen_store_never_holds_the_service(own_store):
    """SIGSTOP: the daemon accepts connections and never answers (as after a desync). A read is
    503 by its deadline, /health answers meanwhile, and all is well once it runs again."""
    daemon, url, c = own_store
    pid = _daemon_pid(daemon)
    os.kill(pid, signal.SIGSTOP)
    try:
        pending: dict = {}
        reader = threading.Thread(target=lambda: pending.update(r=c.post("/ask", json=QUESTION)))
        t0 = time.monotonic()
        reader.start()
        time.sleep(0.3)
        health = httpx.get(url + "/health", timeout=10)
        assert health.status_code == 503 and health.headers.get("Retry-After")
        assert time.monotonic() - t0 < 5
        reader.join(10)
        assert not reader.is_alive() and pending["r"].status_code == 503
        assert pending["r"].headers.get("Retry-After") and time.monotonic() - t0 < QUICK_S + 2
    finally:
        os.kill(pid, signal.SIGCONT)
    deadline = time.monotonic() + 60
    while c.get("/rooms").status_code != 200:
        assert time.monotonic() < deadline, "the service did not recover"
        time.sleep(0.5)
    assert c.get("/rooms").json()[0]["objects"] == 10
