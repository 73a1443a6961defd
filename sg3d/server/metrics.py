"""`GET /metrics` of `sg3d serve`: the Prometheus text format, through `prometheus_client`.

What it counts: requests by method, route template (`/rooms/{building}/{room}/objects`, never the
raw path, so the label set stays small) and status; request latency as a histogram per method and
route; answer-cache hits and misses of `/ask`; and statements sent to the graph store (each one a
round trip; `sg3d.graphdb.store.on_statement` is the one place every statement passes).

With `sg3d serve --workers N` (N > 1) each worker process writes its values to files under
PROMETHEUS_MULTIPROC_DIR (a temporary folder the serve command owns) and a scrape of any worker
reads them all (`prometheus_client.multiprocess`): the figures are the server's, not one worker's.
That variable must be set before this module is imported, which the serve command does before
uvicorn starts its workers.
"""
from __future__ import annotations

import os
import time

from prometheus_client import (
    CONTENT_TYPE_LATEST,
    REGISTRY,
    CollectorRegistry,
    Counter,
    Histogram,
    generate_latest,
    multiprocess,
)

MULTIPROC_ENV = "PROMETHEUS_MULTIPROC_DIR"
CONTENT_TYPE = CONTENT_TYPE_LATEST
UNMATCHED = "unmatched"        # the route label of a path no route serves (a 404)

REQUESTS = Counter("sg3d_http_requests", "HTTP requests answered, by method, route template and status",
                   ["method", "route", "status"])
LATENCY = Histogram("sg3d_http_request_duration_seconds",
                    "Time from a request's arrival to the end of its answer, by method and route template",
                    ["method", "route"],
                    buckets=(0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0))
ANSWER_CACHE = Counter("sg3d_answer_cache", "Answers of /ask served from the answer cache (hit) or computed (miss)",
                       ["result"])
STORE_STATEMENTS = Counter("sg3d_store_statements", "Statements sent to the graph store (round trips)")


def exposition() -> bytes:
    """The current figures in the Prometheus text format: every worker's when several serve."""
    if os.environ.get(MULTIPROC_ENV):
        registry = CollectorRegistry()
        multiprocess.MultiProcessCollector(registry)
        return generate_latest(registry)
    return generate_latest(REGISTRY)


def count_store_statements() -> None:
    """From now on, every statement this process sends to the store is counted."""
    from sg3d.graphdb.store import on_statement

    on_statement(STORE_STATEMENTS.inc)


def count_cache(hit: bool) -> None:
    ANSWER_CACHE.labels("hit" if hit else "miss").inc()


class RequestMetrics:
    """ASGI middleware (outermost): counts and times every HTTP request under its route template,
    refusals of the door (401, 413) included."""

    def __init__(self, app, routes):
        self.app = app
        self.routes = routes

    def _template(self, scope) -> str:
        route = scope.get("route")
        if route is None:                   # refused before routing: find the route it asked for
            from starlette.routing import Match

            route = next((r for r in self.routes() if r.matches(scope)[0] is not Match.NONE), None)
        return getattr(route, "path", None) or UNMATCHED

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        start = time.perf_counter()
        status = 500

        async def sending(message):
            nonlocal status
            if message["type"] == "http.response.start":
                status = message["status"]
            await send(message)

        try:
            await self.app(scope, receive, sending)
        finally:
            method, route = scope.get("method", ""), self._template(scope)
            REQUESTS.labels(method, route, str(status)).inc()
            LATENCY.labels(method, route).observe(time.perf_counter() - start)
