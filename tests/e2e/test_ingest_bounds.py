"""Bounds at the ingest door, and reads that survive a value stored around the door (with
`sg3d cypher --write`): a real server, a real store, a real HTTP client."""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from tests.serve_helpers import kitchen_body

ROUTES = [("get", "/rooms", None), ("get", "/rooms/home/kitchen/objects", None),
          ("get", "/graph?building=home&room=kitchen", None), ("get", "/graph?building=home", None),
          ("post", "/ask", {"question": "what is the biggest object?", "room": "kitchen"}),
          ("post", "/ask", {"question": "how many cups are there?", "room": "kitchen"})]


@pytest.fixture
def client(kitchen_client):
    return kitchen_client


def _edit(fn, observation="bad"):
    body = kitchen_body(observation)
    fn(body)
    return body


def _obj(body, **kw):
    body["graph"]["objects"][0].update(kw)


POISON = {
    "huge mean": lambda b: _obj(b, mean=[1e308, 1e308, 1e308]),
    "huge size": lambda b: _obj(b, size=[1e308, 1.0, 1.0]),
    "zero size": lambda b: _obj(b, size=[0.0, 1.0, 1.0]),
    "huge var": lambda b: _obj(b, var=[1e300, 0.0, 0.0]),
    "nan up": lambda b: b["graph"].update(up=[float("nan")] * 3),
    "zero up": lambda b: b["graph"].update(up=[0.0, 0.0, 0.0]),
    "long up": lambda b: b["graph"].update(up=[0.0, 0.0, 3.0]),
    "overflow int": lambda b: _obj(b, n_points=10 ** 30),
    "long label": lambda b: _obj(b, labels=["x" * 1_000_000], scores=[0.9]),
    "odd label": lambda b: _obj(b, labels=["cup\n<script>"], scores=[0.9]),
    "negative frame": lambda b: _obj(b, frames=[-1, 3]),
    "too many frames": lambda b: b["graph"].update(frames=list(range(200_001))),
    "room newline": lambda b: b.update(room="kit\nchen"),
    "room nul": lambda b: b.update(room="kit\x00chen"),
    "room dots": lambda b: b.update(room=".."),
    "building backslash": lambda b: b.update(building="a\\b"),
    "bad layer": lambda b: _obj(b, layer="ceiling"),
    "bad shape": lambda b: _obj(b, shape="x" * 5000),
    "bad colour2": lambda b: _obj(b, colour2="mauve"),
}


def _all_routes_answer(c):
    for method, path, body in ROUTES:
        r = c.request(method, path, json=body)
        assert r.status_code == 200, (path, r.status_code, r.text[:300])


@pytest.mark.parametrize("name", list(POISON))
def test_an_out_of_bounds_ingest_is_422_and_every_route_still_answers(client, store, name):
    body = _edit(POISON[name])
    for _ in range(2):      # twice: a second copy would merge into the first if the first got in
        text = json.dumps(body)
        r = client.post("/ingest", content=text, headers={"content-type": "application/json"})
        assert r.status_code == 422, (name, r.status_code, r.text[:300])
        assert len(r.content) < 5000, "the error must not echo the input"
        assert r.json()["detail"]
    _all_routes_answer(client)


@pytest.mark.parametrize("literal", ["NaN", "Infinity", "-Infinity"])
def test_nan_and_infinity_json_literals_are_422(client, literal):
    text = json.dumps(kitchen_body("lit")).replace('"mean": [', f'"mean": [{literal}, ', 1)
    r = client.post("/ingest", content=text, headers={"content-type": "application/json"})
    assert r.status_code == 422, r.text[:300]
    assert literal in r.json()["detail"]


def test_deep_nesting_is_422_not_a_recursion_error(client):
    deep = "[" * 100_000 + "]" * 100_000
    r = client.post("/ingest", content=deep, headers={"content-type": "application/json"})
    assert r.status_code == 422 and "nests deeper" in r.json()["detail"]
    goal = "(and " * 900 + "(on a b)" + ")" * 900
    r = client.post("/plan", json={"goal": goal[:2000], "room": "kitchen"})
    assert r.status_code in (400, 422) and "deeper" in r.text, r.text[:300]


def test_a_huge_question_is_refused_without_echo(client):
    r = client.post("/ask", json={"question": "cup " * 500_000, "room": "kitchen"})
    assert r.status_code == 422
    assert len(r.content) < 5000 and "cup cup" not in r.text


def test_unicode_names_are_fine(client, store):
    for room in ("küche", "my room", "кухня"):
        r = client.post("/ingest", json=kitchen_body(f"u-{room}", room=room))
        assert r.status_code == 200, r.text
    names = {r["name"] for r in client.get("/rooms").json()}
    assert {"küche", "my room", "кухня"} <= names


def test_layer_shape_and_second_colour_are_stored(client, store):
    body = kitchen_body("attrs", room="pantry")
    _obj(body, layer="structure", shape="flat", colour2="white")
    assert client.post("/ingest", json=body).status_code == 200
    keys, rows = store.run_raw("MATCH (o:Object) WHERE o.room = 'home/pantry' AND o.layer = 'structure' "
                               "RETURN o.shape, o.colour2")
    assert [tuple(r) for r in rows] == [("flat", "white")]


def _plant_bad_values(store):
    """Values a store written without these bounds can hold."""
    store.run_raw("MATCH (o:Object) WHERE o.room = 'home/kitchen' WITH o ORDER BY o.id LIMIT 1 "
                  "SET o.x = $inf, o.var = [$nan, $nan, $nan], o.volume = $inf",
                  {"inf": float("inf"), "nan": float("nan")}, write=True)
    store.run_raw("MATCH (r:Room {id: 'home/kitchen'}) SET r.up = [$nan, $nan, $nan]",
                  {"nan": float("nan")}, write=True)


def test_reads_skip_a_stored_bad_value_and_db_check_repairs_it(client, store, embedded_home, caplog):
    from sg3d.cli import cli

    _plant_bad_values(store)
    with caplog.at_level("WARNING", logger="sg3d.store"):
        _all_routes_answer(client)
    assert "db check --repair" in caplog.text
    objects = client.get("/rooms/home/kitchen/objects").json()
    assert len(objects) == 9

    runner = CliRunner()
    found = runner.invoke(cli, ["--home", str(embedded_home), "db", "check", "--json"])
    assert found.exit_code == 1, found.output      # found, not repaired
    report = json.loads(found.output)
    assert len(report["objects"]) == 1 and report["rooms"] == ["home/kitchen"] and not report["repaired"]
    fixed = runner.invoke(cli, ["--home", str(embedded_home), "db", "check", "--repair"])
    assert fixed.exit_code == 0 and "removed 1 object" in fixed.output, fixed.output
    again = runner.invoke(cli, ["--home", str(embedded_home), "db", "check"])
    assert "no unusable values" in again.output
    assert client.post("/ask", json={"question": "how many objects are there?", "room": "kitchen"}).status_code == 200


@pytest.mark.parametrize("room", ["a/b", "..", "kit\nchen", " x"])
def test_build_refuses_a_bad_room_name(tmp_path, room):
    from sg3d.cli import cli

    r = CliRunner().invoke(cli, ["--home", str(tmp_path), "build", str(tmp_path), "--room", room])
    assert r.exit_code == 2 and "--room" in r.output
