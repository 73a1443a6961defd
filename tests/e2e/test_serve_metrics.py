"""`GET /metrics` of a real `sg3d serve`, read by prometheus_client's own parser."""
from __future__ import annotations

import httpx
import pytest
from prometheus_client.parser import text_string_to_metric_families

from tests.serve_helpers import kitchen_body, serve_process


def _samples(base: str) -> dict:
    """{(sample name, frozenset of labels): value} of one scrape (no token: like /health)."""
    r = httpx.get(base + "/metrics", timeout=10)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/plain")
    return {(s.name, frozenset(s.labels.items())): s.value
            for family in text_string_to_metric_families(r.text) for s in family.samples}


def _value(samples: dict, name: str, **labels) -> float:
    return samples.get((name, frozenset(labels.items())), 0.0)


@pytest.mark.parametrize("workers", [1, 2])
def test_metrics_count_requests_per_route_template_cache_and_store_round_trips(tmp_path, workers):
    """With two worker processes a scrape (answered by either) adds up both workers' figures."""
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.server.auth import ensure_token

    home = tmp_path / "home"
    daemon = EmbeddedServer(home)
    daemon.ensure_running()
    token = ensure_token(home)
    try:
        with serve_process(home, "--workers", str(workers)) as base, httpx.Client(base_url=base, timeout=120,
                                                       headers={"Authorization": f"Bearer {token}"}) as c:
            assert c.post("/ingest", json=kitchen_body()).status_code == 200
            before = _samples(base)
            question = {"question": "how many cups are there?", "room": "kitchen"}
            for _ in range(3):
                assert c.post("/ask", json=question).status_code == 200
            for room in ("kitchen", "nowhere"):
                c.get(f"/rooms/home/{room}/objects")
            assert httpx.get(base + "/rooms").status_code == 401          # refused at the door
            after = _samples(base)
    finally:
        daemon.stop()

    def moved(name, **labels):
        return _value(after, name, **labels) - _value(before, name, **labels)

    assert moved("sg3d_http_requests_total", method="POST", route="/ask", status="200") == 3
    objects = "/rooms/{building}/{room}/objects"
    assert moved("sg3d_http_requests_total", method="GET", route=objects, status="200") == 1
    assert moved("sg3d_http_requests_total", method="GET", route=objects, status="404") == 1
    assert moved("sg3d_http_requests_total", method="GET", route="/rooms", status="401") == 1
    assert not any(dict(labels).get("route", "").startswith("/rooms/home") for _, labels in after)
    assert moved("sg3d_http_request_duration_seconds_count", method="POST", route="/ask") == 3
    assert moved("sg3d_http_request_duration_seconds_bucket", method="POST", route="/ask", le="+Inf") == 3
    # the same question three times, nothing written between: computed once (per worker), then kept
    misses, hits = moved("sg3d_answer_cache_total", result="miss"), moved("sg3d_answer_cache_total", result="hit")
    assert misses + hits == 3 and (misses == 1 if workers == 1 else 1 <= misses <= 2), (misses, hits)
    assert moved("sg3d_store_statements_total") >= 3
