"""`sg3d serve` after a burst: more concurrent calls than the worker pool holds, a quiet spell,
then every call still runs (a real server on a small pool, a real store, real clients)."""
from __future__ import annotations

import asyncio
import threading
import time

import httpx
import pytest

from tests.serve_helpers import kitchen_body, running_server

POOL = 4            # worker threads: a burst of BURST is 15 times what the pool runs at once
BURST = 60
AFTER = 20          # fewer calls after the quiet than the burst's excess over the pool
QUIET_S = 2.5       # longer than any idle timeout a pool of this size would be given in a test
QUICK_S = 8.0       # a read's deadline: a call that never runs is a 503 after it


@pytest.fixture(scope="module")
def small_pool(store_session, embedded_home):
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    token = ensure_token(embedded_home)
    with running_server(Settings(home=embedded_home), token, max_threads=POOL, quick_timeout_s=QUICK_S) as url:
        yield url, token


async def _ask_all(url: str, token: str, n: int) -> list[tuple[int, float]]:
    """`n` concurrent POST /ask, each on its own connection: (status, seconds) each."""
    async def one(i: int) -> tuple[int, float]:
        async with httpx.AsyncClient(base_url=url, headers={"Authorization": f"Bearer {token}"},
                                     timeout=QUICK_S + 30) as c:
            t0 = time.perf_counter()
            r = await c.post("/ask", json={"question": "how many cups are on the table?", "room": "kitchen"})
            return r.status_code, time.perf_counter() - t0
    return list(await asyncio.gather(*(one(i) for i in range(n))))


def _pool_threads() -> int:
    return sum(1 for t in threading.enumerate() if t.name == "sg3d-call" and t.is_alive())


def test_every_call_runs_after_a_burst_past_the_pool_and_a_quiet_spell(small_pool, store):
    url, token = small_pool
    ingest = httpx.post(url + "/ingest", json=kitchen_body(), headers={"Authorization": f"Bearer {token}"},
                        timeout=120)
    assert ingest.status_code == 200, ingest.text[:300]
    burst = asyncio.run(_ask_all(url, token, BURST))
    assert [s for s, _ in burst] == [200] * BURST
    kept = _pool_threads()
    time.sleep(QUIET_S)
    after = asyncio.run(_ask_all(url, token, AFTER))
    statuses = [s for s, _ in after]
    assert statuses == [200] * AFTER, f"{AFTER - statuses.count(200)} of {AFTER} calls unanswered after the quiet"
    assert max(t for _, t in after) < QUICK_S
    assert _pool_threads() >= kept           # the pool's threads are kept through the quiet


async def _health_all(url: str, n: int) -> list[int]:
    """`n` concurrent GET /health, each on its own connection: the statuses."""
    async with httpx.AsyncClient(base_url=url, timeout=60,
                                 limits=httpx.Limits(max_connections=None, max_keepalive_connections=0)) as c:
        replies = await asyncio.gather(*(c.get("/health") for _ in range(n)))
    return [r.status_code for r in replies]


def test_a_burst_of_health_checks_finds_the_store_up(served, store):
    """Each /health looks at the store's Bolt port (the default pool: 64 at a time); 200 at once
    had the port's accept queue overflow, read the store as down and reconnect under the other
    calls."""
    url, _ = served
    for _ in range(2):
        statuses = asyncio.run(_health_all(url, 200))
        assert statuses == [200] * 200, f"{200 - statuses.count(200)} of 200 not 200: {sorted(set(statuses))}"
