"""`sg3d serve` end to end: uvicorn on a free loopback port, a real store, a real HTTP client."""
from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor

import httpx
import pytest

from tests.serve_helpers import kitchen_body, running_server

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROUTES = [("post", "/ask"), ("post", "/plan"), ("get", "/rooms"), ("get", "/rooms/home/kitchen/objects"),
          ("get", "/graph"), ("post", "/ingest")]


@pytest.fixture
def client(served, store):
    url, token = served
    with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=60) as c:
        yield c


@pytest.fixture
def kitchen(client, store):
    r = client.post("/ingest", json=kitchen_body())
    assert r.status_code == 200, r.text
    return client


def n_objects(store) -> int:
    return store.read("object_total")[0]["n"]


def test_token_file_is_private_and_stable(embedded_home, served):
    from sg3d.server.auth import ensure_token, token_path

    path = token_path(embedded_home)
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert ensure_token(embedded_home) == served[1] == path.read_text().strip()
    assert len(served[1]) >= 40


def test_health_needs_no_token(served):
    r = httpx.get(served[0] + "/health")
    assert r.status_code == 200
    from sg3d import __version__
    assert r.json() == {"status": "ok", "store": True, "state": "up", "version": __version__}


@pytest.mark.parametrize("method,path", ROUTES)
def test_every_route_refuses_a_missing_or_wrong_token(served, method, path):
    url, token = served
    for headers in ({}, {"Authorization": f"Bearer {token}x"}, {"Authorization": f"Basic {token}"}):
        r = httpx.request(method, url + path, headers=headers, json={})
        assert r.status_code == 401, (path, headers, r.text)
        assert r.headers["www-authenticate"] == "Bearer"


def test_openapi_and_docs(client):
    spec = client.get("/openapi.json").json()
    assert {"/health", "/ask", "/plan", "/rooms", "/rooms/{building}/{room}/objects", "/graph",
            "/ingest"} <= set(spec["paths"])
    assert "IngestRequest" in spec["components"]["schemas"]
    assert client.get("/docs").status_code == 200


def test_ingest_merges_one_transaction_and_idempotently(client, store):
    r = client.post("/ingest", json=kitchen_body("obs-1"))
    assert r.status_code == 200, r.text
    first = r.json()
    assert (first["created"], first["updated"], first["relations"], first["skipped"]) == (10, 0, 7, False)
    assert first["room_objects"] == n_objects(store) == 10
    again = client.post("/ingest", json=kitchen_body("obs-1")).json()
    assert again["skipped"] and again["created"] == 0 and n_objects(store) == 10
    # a new observation of the same objects is matched to them (same-node detection), not added
    other = client.post("/ingest", json=kitchen_body("obs-2")).json()
    assert (other["created"], other["updated"], other["skipped"]) == (0, 10, False)
    assert n_objects(store) == 10
    rows = store.read("vqa_objects_in_rooms", rooms=["home/kitchen"], labels=["cup"], colour=None, limit=10)
    assert len(rows) == 3


def _bad_bodies():
    def edit(fn):
        body = kitchen_body("bad")
        fn(body)
        return body
    yield "hist", edit(lambda b: b["graph"]["objects"][0].update(hist=[1.0] * 3))
    yield "predicate", edit(lambda b: b["graph"]["relations"][0].update(predicate="LOVES"))
    yield "subject", edit(lambda b: b["graph"]["relations"][0].update(subject="ghost"))
    yield "room", edit(lambda b: b.pop("room"))
    yield "observation_id", edit(lambda b: b.pop("observation_id"))
    yield "scores", edit(lambda b: b["graph"]["objects"][1].update(scores=[1.5]))
    yield "colour", edit(lambda b: b["graph"]["objects"][2].update(colour="mauve"))
    yield "thumbnail", edit(lambda b: b["graph"]["objects"][2].update(thumbnail="bm90IGEganBlZw=="))
    yield "mean", edit(lambda b: b["graph"]["objects"][3].update(mean=[0, 0]))
    yield "weight", edit(lambda b: b["graph"]["objects"][3].update(weight=3))
    yield "building", edit(lambda b: b.update(building="a/b"))


@pytest.mark.parametrize("field,body", list(_bad_bodies()), ids=[f for f, _ in _bad_bodies()])
def test_bad_ingest_is_422_naming_the_field_and_writes_nothing(kitchen, store, field, body):
    before = n_objects(store), store.read("relation_count", room="home/kitchen", types=["ON", "IN", "NEXT_TO", "NEAR"])
    r = kitchen.post("/ingest", json=body)
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert any(field in [str(p) for p in d["loc"]] or field in d["msg"] for d in detail), detail
    assert (n_objects(store), store.read("relation_count", room="home/kitchen",
                                         types=["ON", "IN", "NEXT_TO", "NEAR"])) == before


def test_rooms_and_objects(kitchen):
    rooms = kitchen.get("/rooms").json()
    assert [(r["building"], r["id"], r["objects"]) for r in rooms] == [("home", "home/kitchen", 10)]
    assert kitchen.get("/rooms", params={"building": "elsewhere"}).json() == []
    cups = kitchen.get("/rooms/home/kitchen/objects", params={"label": "cup"}).json()
    assert sorted(o["name"] for o in cups) == ["blue cup", "red cup", "white cup"]
    red = kitchen.get("/rooms/home/kitchen/objects", params={"colour": "red"}).json()
    assert [o["name"] for o in red] == ["red cup"]
    near = kitchen.get("/rooms/home/kitchen/objects", params={"near": "2.6,0,1.0", "radius": 0.5}).json()
    assert [o["label"] for o in near] == ["microwave", "bottle"]
    assert near[0]["distance"] <= near[1]["distance"] <= 0.5
    assert len(kitchen.get("/rooms/home/kitchen/objects").json()) == 10
    assert kitchen.get("/rooms/home/attic/objects").status_code == 404
    assert kitchen.get("/rooms/home/kitchen/objects", params={"near": "1,2"}).status_code == 400


def test_ask_gives_the_json_of_the_cli(kitchen, embedded_home):
    from click.testing import CliRunner

    from sg3d.cli import cli

    question = "how many cups are on the table?"
    r = kitchen.post("/ask", json={"question": question, "room": "kitchen"})
    assert r.status_code == 200, r.text
    got = r.json()
    assert got["ok"] and got["value"] == 3 and got["form"] == "count"
    out = CliRunner().invoke(cli, ["--home", str(embedded_home), "ask", question, "--room", "kitchen", "--json"])
    assert out.exit_code == 0, out.output
    cli_json = json.loads(out.output)
    got.pop("thumbnail_jpeg_base64")
    assert got == cli_json
    refused = kitchen.post("/ask", json={"question": "paint the moon", "room": "kitchen"}).json()
    assert refused["ok"] is False and refused["answer"]
    assert kitchen.post("/ask", json={"room": "kitchen"}).status_code == 422


def test_plan(kitchen):
    r = kitchen.post("/plan", json={"command": "put the red cup in the sink", "room": "kitchen"})
    assert r.status_code == 200, r.text
    plan = r.json()
    assert plan["valid"] and plan["room"] == "home/kitchen"
    assert plan["goal"] == ["(in red_cup sink)"]
    assert [s["action"] for s in plan["plan"]][-1] == "put-in"
    assert "(define (domain" in plan["domain_pddl"] and "red_cup" in plan["problem_pddl"]
    bad = kitchen.post("/plan", json={"command": "put the red cup in the sink", "room": "attic"})
    assert bad.status_code == 400 and "attic" in bad.json()["detail"]


def test_graph_export(kitchen):
    g = kitchen.get("/graph", params={"building": "home", "room": "kitchen"}).json()
    assert len(g["nodes"]) == 10 and len(g["edges"]) == 7
    assert "red cup" in {n["name"] for n in g["nodes"]}
    xml = kitchen.get("/graph", params={"building": "home", "format": "graphml"})
    assert xml.status_code == 200 and xml.headers["content-type"].startswith("application/graphml+xml")
    root = ET.fromstring(xml.text)
    assert len(root.findall(".//{http://graphml.graphdrawing.org/xmlns}node")) == 10
    assert kitchen.get("/graph", params={"building": "nowhere"}).status_code == 404
    assert kitchen.get("/graph", params={"format": "dot"}).status_code == 422


def test_concurrent_requests(kitchen, served):
    url, token = served
    questions = ["how many cups are on the table?", "what is on the table?", "is there a sink?",
                 "where is the bottle?", "how many chairs are in the room?"]

    def client_run(i):
        with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=60) as c:
            return [c.post("/ask", json={"question": q, "room": "kitchen"}) for q in questions]

    with ThreadPoolExecutor(16) as pool:
        results = [r for rs in pool.map(client_run, range(16)) for r in rs]
    assert all(r.status_code == 200 for r in results)
    by_q = {}
    for r in results:
        by_q.setdefault(r.json()["question"], set()).add(r.json()["answer"])
    assert all(len(answers) == 1 for answers in by_q.values()), by_q


def test_survives_a_restart_of_the_embedded_store(tmp_path):
    """Its own store (the session's must not move): stop it and start it again on new ports; the
    running service finds it again."""
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    home = tmp_path / "home"
    daemon = EmbeddedServer(home)
    first = daemon.ensure_running()
    try:
        token = ensure_token(home)
        with running_server(Settings(home=home), token) as url:
            c = httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120)
            assert c.post("/ingest", json=kitchen_body()).status_code == 200
            before = c.post("/ask", json={"question": "how many cups are there?"}).json()["answer"]
            daemon.stop()
            second = daemon.start()
            assert second.bolt_port != first.bolt_port or second.pid != first.pid
            after = c.post("/ask", json={"question": "how many cups are there?"})
            assert after.status_code == 200 and after.json()["answer"] == before
            assert c.get("/health").json()["store"] is True
    finally:
        daemon.stop()


def test_sg3d_serve_command(tmp_path, embedded_home, store_session):
    """The console command itself: starts, writes the token file 0600, answers, warns about a
    non-loopback host (checked without binding one)."""
    from sg3d.graphdb.embedded import free_port
    from sg3d.server.http import is_loopback

    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.5")
    port = free_port()
    env = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(embedded_home), "serve", "--port", str(port)],
                            stderr=subprocess.PIPE, text=True, env=env)
    try:
        deadline = time.monotonic() + 90
        while True:
            try:
                if httpx.get(f"http://127.0.0.1:{port}/health").status_code == 200:
                    break
            except httpx.TransportError:
                pass
            assert proc.poll() is None and time.monotonic() < deadline, proc.stderr.read() if proc.poll() else "timeout"
            time.sleep(0.2)
        token = (embedded_home / "api-token").read_text().strip()
        assert httpx.get(f"http://127.0.0.1:{port}/rooms").status_code == 401
        assert httpx.get(f"http://127.0.0.1:{port}/rooms", headers={"Authorization": f"Bearer {token}"}).status_code == 200
    finally:
        proc.terminate()
        proc.wait(20)
    assert "api-token" in proc.stderr.read()
