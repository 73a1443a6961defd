"""Request bodies at `sg3d serve`'s door: a route that takes none is sent none (refused before a
byte is read), and nobody's body holds the event loop: /health keeps answering while another
client posts 15 MB bodies in a loop. A real server, raw sockets and a real client."""
from __future__ import annotations

import socket
import threading
import time
from urllib.parse import urlsplit

import httpx
import pytest

from tests.serve_helpers import reply_status, running_server

BODY = b"[" + b"1," * (7_500_000 - 1) + b"1]"      # 15 MB of valid JSON


@pytest.fixture(scope="module")
def server(store_session, embedded_home):
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    token = ensure_token(embedded_home)
    with running_server(Settings(home=embedded_home), token) as url:
        yield url, token


def post_raw(url: str, path: str, body: bytes, token=None) -> int:
    """POST `body` to `path` on a fresh connection: the reply's status (0 when none came)."""
    parts = urlsplit(url)
    head = [f"POST {path} HTTP/1.1", f"Host: {parts.hostname}", "Content-Type: application/json",
            f"Content-Length: {len(body)}"]
    if token:
        head.append(f"Authorization: Bearer {token}")
    sock = socket.create_connection((parts.hostname, parts.port), timeout=60)
    try:
        try:
            sock.sendall(("\r\n".join(head) + "\r\n\r\n").encode() + body)
        except (BrokenPipeError, ConnectionResetError):
            pass          # answered and closed before the whole body went: the point
        return reply_status(sock)
    finally:
        sock.close()


def _health_while_posting(url: str, path: str, token=None, seconds: float = 12.0) -> tuple[list[float], list[int]]:
    """GET /health every 50 ms from one client while another posts BODY to `path` in a loop:
    (the /health latencies in seconds, the statuses the poster got)."""
    stop = threading.Event()
    statuses: list[int] = []

    def poster():
        while not stop.is_set():
            statuses.append(post_raw(url, path, BODY, token))

    thread = threading.Thread(target=poster, daemon=True)
    thread.start()
    took = []
    try:
        with httpx.Client(base_url=url, timeout=60) as c:
            c.get("/health")
            end = time.monotonic() + seconds
            while time.monotonic() < end:
                t0 = time.perf_counter()
                assert c.get("/health").status_code == 200
                took.append(time.perf_counter() - t0)
                time.sleep(0.05)
    finally:
        stop.set()
        thread.join(120)
    return took, statuses


def p95(values: list[float]) -> float:
    ordered = sorted(values)
    return ordered[int(0.95 * (len(ordered) - 1))]


def test_health_answers_while_another_client_posts_15_mb_to_it_without_a_token(server):
    url, _ = server
    took, statuses = _health_while_posting(url, "/health")
    assert len(took) > 20 and p95(took) < 0.5, f"/health p95 {p95(took):.2f} s, max {max(took):.2f} s"
    assert statuses and set(statuses) == {413}, statuses[:10]


@pytest.mark.parametrize("path", ["/health", "/docs", "/openapi.json"])
def test_a_body_on_a_route_that_takes_none_is_refused_before_it_is_read(server, path):
    url, _ = server
    t0 = time.monotonic()
    assert post_raw(url, path, BODY) == 413
    assert time.monotonic() - t0 < 2


def test_a_body_on_a_get_route_is_refused_even_with_the_token(server):
    url, token = server
    r = httpx.request("GET", url + "/rooms", content=b'{"x": 1}', headers={"Authorization": f"Bearer {token}"})
    assert r.status_code == 413 and "takes no request body" in r.json()["detail"]
    assert httpx.get(url + "/rooms", headers={"Authorization": f"Bearer {token}"}).status_code == 200
    assert httpx.post(url + "/health").status_code == 405        # no body: the route's own answer


def test_bodies_with_the_token_are_parsed_off_the_event_loop(server):
    url, token = server
    took, statuses = _health_while_posting(url, "/ingest", token, seconds=8.0)
    assert len(took) > 10 and p95(took) < 1.0, f"/health p95 {p95(took):.2f} s, max {max(took):.2f} s"
    assert statuses and set(statuses) == {422}, statuses[:10]
