"""A real `sg3d serve` application on a free loopback port (uvicorn in a thread) and the JSON
body of a hand-made kitchen for POST /ingest."""
from __future__ import annotations

import threading
import time
from contextlib import contextmanager

from tests.test_planning import KITCHEN_RELATIONS, kitchen_objects


def kitchen_body(observation_id: str = "obs-1", building: str = "home", room: str = "kitchen") -> dict:
    """Ten objects and seven relations (tests/test_planning.py's kitchen) as local graph JSON."""
    objects = [{"id": o.local_id, "labels": o.labels, "scores": o.scores, "mean": list(o.mean),
                "var": list(o.var), "n_points": o.n_points, "size": list(o.size),
                "hist": [float(v) for v in o.hist], "colour": "grey" if o.colour == "gray" else o.colour,
                "frames": [3, 4, 9]} for o in kitchen_objects()]
    relations = [{"subject": s, "predicate": p, "object": o, "score": sc} for s, p, o, sc in KITCHEN_RELATIONS]
    return {"building": building, "room": room, "observation_id": observation_id,
            "graph": {"objects": objects, "relations": relations, "frames": [3, 4, 9]}}


@contextmanager
def running_server(settings, token: str, **app_options):
    """Serve `create_app(settings, token, **app_options)` with uvicorn on a free loopback port;
    yields the base URL."""
    import uvicorn

    from graphdb.embedded import free_port
    from sg3d.server.http import create_app

    api = create_app(settings, token, **app_options)
    port = free_port()
    server = uvicorn.Server(uvicorn.Config(api, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if not thread.is_alive() or time.monotonic() > deadline:
            raise RuntimeError("uvicorn did not start")
        time.sleep(0.02)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(10)
        api.state.stores.close()
