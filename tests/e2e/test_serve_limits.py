"""The server's door: the token before the body, a body size limit before the body is read, and
resident memory that does not follow what a caller sends. A real server, raw sockets."""
from __future__ import annotations

import socket
import time
from urllib.parse import urlsplit

import httpx
import pytest

from tests.serve_helpers import kitchen_body, reply_status, running_server

BIG = 119 * 1024 * 1024
CHUNK = b"[" + b"1," * (512 * 1024 - 1) + b"1"   # ~1 MB of a JSON list, sent again and again


@pytest.fixture(scope="module")
def small_limit_server(store_session, embedded_home):
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    token = ensure_token(embedded_home)
    with running_server(Settings(home=embedded_home), token, max_body=1024 * 1024) as url:
        yield url, token


def _rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS")


def _send_big(url: str, token, declare_length: bool) -> int:
    """POST /ingest with a 119 MB body over a raw socket; the status line's code (or 0 when the
    server closed without one)."""
    parts = urlsplit(url)
    head = ["POST /ingest HTTP/1.1", f"Host: {parts.hostname}", "Content-Type: application/json"]
    head.append(f"Content-Length: {BIG}" if declare_length else "Transfer-Encoding: chunked")
    if token:
        head.append(f"Authorization: Bearer {token}")
    sock = socket.create_connection((parts.hostname, parts.port), timeout=30)
    try:
        sock.sendall(("\r\n".join(head) + "\r\n\r\n").encode())
        sent = 0
        try:
            while sent < BIG:
                data = CHUNK if declare_length else b"%x\r\n%s\r\n" % (len(CHUNK), CHUNK)
                sock.sendall(data)
                sent += len(CHUNK)
        except (BrokenPipeError, ConnectionResetError, socket.timeout):
            pass           # the server answered and closed: the point of the limit
        sock.settimeout(10)
        return reply_status(sock)
    finally:
        sock.close()


@pytest.mark.parametrize("declare_length", [True, False], ids=["content-length", "chunked"])
def test_a_huge_body_without_token_is_401_and_memory_stays_flat(small_limit_server, declare_length):
    url, token = small_limit_server
    before = _rss_mb()
    t0 = time.monotonic()
    status = _send_big(url, None, declare_length)
    assert status == 401
    assert _rss_mb() - before < 50
    assert time.monotonic() - t0 < 30


@pytest.mark.parametrize("declare_length", [True, False], ids=["content-length", "chunked"])
def test_a_huge_body_with_token_is_413_and_memory_stays_flat(small_limit_server, declare_length):
    url, token = small_limit_server
    before = _rss_mb()
    status = _send_big(url, token, declare_length)
    assert status == 413
    assert _rss_mb() - before < 50


def test_malformed_json_without_token_is_401(small_limit_server):
    url, _ = small_limit_server
    r = httpx.post(url + "/ingest", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 401


def test_the_limit_lets_normal_bodies_through(small_limit_server, store):
    url, token = small_limit_server
    r = httpx.post(url + "/ingest", json=kitchen_body("fits"), headers={"Authorization": f"Bearer {token}"},
                   timeout=60)
    assert r.status_code == 200, r.text[:300]
    r = httpx.post(url + "/ask", json={"question": "x" * 2_000_000},
                   headers={"Authorization": f"Bearer {token}"})
    assert r.status_code == 413 and "--max-body" in r.json()["detail"] and len(r.content) < 1000


def test_serve_help_documents_max_body():
    from click.testing import CliRunner

    from sg3d.cli import cli

    out = CliRunner().invoke(cli, ["serve", "--help"]).output
    assert "--max-body" in out and "413" in out


def test_served_connections_do_not_wait_for_delayed_acks():
    """The listening socket says it is TCP, so asyncio turns Nagle's algorithm off on every
    accepted connection (with proto 0 each small response waited ~40 ms for the client's ACK)."""
    import asyncio

    from sg3d.commands.serve import _bind
    from sg3d.graphdb.embedded import free_port

    sock = _bind("127.0.0.1", free_port())
    seen = {}

    async def run():
        async def handle(reader, writer):
            seen["nodelay"] = writer.get_extra_info("socket").getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY)
            writer.close()

        server = await asyncio.start_server(handle, sock=sock)
        port = sock.getsockname()[1]
        _, w = await asyncio.open_connection("127.0.0.1", port)
        for _ in range(100):
            if seen:
                break
            await asyncio.sleep(0.01)
        w.close()
        server.close()

    asyncio.run(run())
    assert seen.get("nodelay") == 1
