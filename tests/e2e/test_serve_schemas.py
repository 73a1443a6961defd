"""`sg3d serve`'s typed responses: /openapi.json documents a response schema for every route, and
what the real routes answer matches it (a real store, uvicorn, a real client); where a route's
call runs (`sg3d.server.dispatch`)."""
from __future__ import annotations

import asyncio
import threading

import httpx
import pytest
from pydantic import TypeAdapter

from tests.serve_helpers import kitchen_body

AUTHED = {("post", "/ask"), ("post", "/plan"), ("get", "/rooms"), ("get", "/rooms/{building}/{room}"),
          ("get", "/rooms/{building}/{room}/objects"),
          ("get", "/graph"), ("post", "/ingest")}


@pytest.fixture
def kitchen(kitchen_client):
    return kitchen_client


def _resolve(spec: dict, schema: dict) -> dict:
    if "$ref" in schema:
        return spec["components"]["schemas"][schema["$ref"].rsplit("/", 1)[1]]
    if schema.get("type") == "array":
        return _resolve(spec, schema["items"])
    return schema


def _json_schema(spec: dict, op: dict, status: str) -> dict:
    return _resolve(spec, op["responses"][status]["content"]["application/json"]["schema"])


def test_openapi_lists_a_response_schema_for_every_route(kitchen):
    spec = kitchen.get("/openapi.json").json()
    ops = {(m, p): op for p, item in spec["paths"].items() for m, op in item.items()}
    assert AUTHED | {("get", "/health"), ("get", "/metrics")} == set(ops)
    assert any(t.startswith("text/plain") for t in ops["get", "/metrics"]["responses"]["200"]["content"])
    for key, op in ops.items():
        if key == ("get", "/metrics"):       # the Prometheus text format, not JSON
            continue
        body = _json_schema(spec, op, "200")
        assert body.get("properties"), (key, body)      # a named model, not an empty "any"
        assert body.get("required"), key
    for key in AUTHED:
        for status in ("401", "413", "422", "503"):
            assert _json_schema(spec, ops[key], status)["properties"]["detail"], (key, status)
    assert _json_schema(spec, ops["get", "/health"], "503")["title"] == "Health"
    assert "application/graphml+xml" in ops["get", "/graph"]["responses"]["200"]["content"]


def _model(api, method: str, path: str):
    route = next(r for r in api.routes if getattr(r, "path", None) == path and method.upper() in r.methods)
    return TypeAdapter(route.response_model)


def test_real_responses_match_their_documented_models(kitchen, served, embedded_home):
    from sg3d.server import schemas
    from sg3d.server.http import create_app
    from sg3d.settings import Settings

    api = create_app(Settings(home=embedded_home), served[1])     # for its routes' response models
    answers = {
        ("post", "/ask"): [kitchen.post("/ask", json={"question": q, "room": "kitchen"}) for q in
                           ("how many cups are on the table?", "which cup is the biggest?", "what is on the table?",
                            "where is the bottle?", "is there a sink?", "paint the moon")],
        ("post", "/plan"): [kitchen.post("/plan", json={"command": "put the red cup in the sink", "room": "kitchen"})],
        ("get", "/rooms"): [kitchen.get("/rooms")],
        ("get", "/rooms/{building}/{room}"): [kitchen.get("/rooms/home/kitchen")],
        ("get", "/rooms/{building}/{room}/objects"): [
            kitchen.get("/rooms/home/kitchen/objects"),
            kitchen.get("/rooms/home/kitchen/objects", params={"near": "2.6,0,1.0", "radius": 0.5})],
        ("get", "/graph"): [kitchen.get("/graph", params={"building": "home", "room": "kitchen"})],
        ("post", "/ingest"): [kitchen.post("/ingest", json=kitchen_body("obs-2"))],
        ("get", "/health"): [httpx.get(served[0] + "/health")],
    }
    for (method, path), replies in answers.items():
        model = _model(api, method, path)
        for r in replies:
            assert r.status_code == 200, (path, r.text)
            model.validate_python(r.json())
            if path == "/ask":       # every documented field is there, even when null
                assert set(schemas.AskAnswer.model_fields) <= set(r.json())
    error = TypeAdapter(schemas.Error)
    error.validate_python(kitchen.get("/rooms/home/attic/objects").json())
    assert kitchen.get("/rooms/home/attic").status_code == 404
    error.validate_python(httpx.get(served[0] + "/rooms").json())
    TypeAdapter(schemas.ValidationFailure).validate_python(kitchen.post("/ask", json={"room": "kitchen"}).json())


def test_no_store_call_runs_on_the_event_loop():
    """A call that blocks (a store that stopped answering) must never freeze the service: every
    call runs in a worker thread, alone or together with others."""
    from sg3d.server.dispatch import Dispatcher

    calls = Dispatcher()
    loop_thread = threading.get_ident()

    def where():
        return threading.get_ident()

    async def alone():
        return await calls.quick(where)

    async def together(n):
        return await asyncio.gather(*(calls.quick(where) for _ in range(n)))

    async def long_one():
        return await calls.pooled(where)

    assert asyncio.run(alone()) != loop_thread
    assert loop_thread not in asyncio.run(together(5))
    assert asyncio.run(long_one()) != loop_thread
    assert calls.in_flight == 0


def test_a_failing_call_raises_and_the_next_one_still_runs():
    from sg3d.server.dispatch import Dispatcher

    calls = Dispatcher()

    def fail():
        raise ValueError("no")

    async def both():
        for run in (calls.quick, calls.pooled):
            with pytest.raises(ValueError):
                await run(fail)

    asyncio.run(both())
    assert calls.in_flight == 0

    async def alone():
        return await calls.quick(threading.get_ident)

    loop_thread = threading.get_ident()
    assert asyncio.run(alone()) != loop_thread     # after a failure, as before it: a worker thread
    assert calls.in_flight == 0
