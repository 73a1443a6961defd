"""A failure that is not the caller's is answered (5xx, `{"detail": ...}`), reaches the server's
log, and leaves the kept-alive connection usable: the client's next request on the same
connection is answered. A real server (the real application, plus one route that fails the way
an unforeseen error would), a real keep-alive client."""
from __future__ import annotations

import http.client
import json
import logging
from urllib.parse import urlsplit

import pytest

from tests.serve_helpers import serving


def _failing_app(settings, token: str, exc: Exception):
    from sg3d.server.http import create_app

    api = create_app(settings, token)

    @api.get("/fails")
    async def fails():
        raise exc
    return api


@pytest.mark.parametrize("exc, status", [(RuntimeError("unforeseen"), 500), ("ServiceUnavailable", 503)],
                         ids=["internal", "store unreachable"])
def test_a_5xx_keeps_the_connection_and_reaches_the_log(store_session, embedded_home, exc, status, caplog):
    from neo4j.exceptions import ServiceUnavailable

    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    if exc == "ServiceUnavailable":
        exc = ServiceUnavailable("the store's port refused the connection")
    token = ensure_token(embedded_home)
    api = _failing_app(Settings(home=embedded_home), token, exc)
    headers = {"Authorization": f"Bearer {token}"}
    try:
        with serving(api) as url, caplog.at_level(logging.ERROR):
            parts = urlsplit(url)
            conn = http.client.HTTPConnection(parts.hostname, parts.port, timeout=30)
            for _ in range(3):
                conn.request("GET", "/fails", headers=headers)
                reply = conn.getresponse()
                body = reply.read()
                assert reply.status == status and "detail" in json.loads(body)
                assert (reply.getheader("connection") or "").lower() != "close"
                conn.request("GET", "/rooms", headers=headers)     # the same connection
                reply = conn.getresponse()
                reply.read()
                assert reply.status == 200
            conn.close()
    finally:
        api.state.stores.close()
    logged = [r for r in caplog.records if r.exc_info and r.exc_info[1] is exc]
    assert logged, "the failure did not reach the server's log"
