"""Where a route runs its application-layer call: on the event loop or in the thread pool.

The application layer and the store driver are synchronous. A plain (sync) FastAPI route runs in
anyio's thread pool, which costs every request two thread hand-offs (event loop -> worker ->
event loop), a large share of a millisecond-scale answer. A request that is alone in the server
gains nothing from that hand-off, so it runs on the event loop directly; as soon as another
request is in flight, calls go to the thread pool, where concurrent requests overlap their waits
on the store. Only quick reads take the direct path; long calls (plans, exports, ingests) always
go to the pool, so the event loop is never held for long. After a call that failed (a store that
is restarting makes the driver retry for up to its retry time), calls go to the pool until one
succeeds, so a store outage holds the event loop for one request at most.
"""
from __future__ import annotations

from typing import Callable, TypeVar

import anyio.lowlevel
from starlette.concurrency import run_in_threadpool

T = TypeVar("T")


class Dispatcher:
    """Counts the calls in flight in this server (one event loop) and places each new one."""

    def __init__(self) -> None:
        self.in_flight = 0
        self.last_ok = True        # whether the last call that ended succeeded

    async def quick(self, fn: Callable[[], T]) -> T:
        """`fn()` for a quick read: inline when it is the only call in flight, else in the pool.

        Lone-request rule: the call registers, then yields once to the event loop, so requests
        that arrived in the same read of the sockets register too before any of them chooses;
        only a call that still finds itself alone, after a call that succeeded, runs inline."""
        self.in_flight += 1
        try:
            await anyio.lowlevel.checkpoint()
            if self.in_flight == 1 and self.last_ok:
                return self._noted(fn)
            return await run_in_threadpool(self._noted, fn)
        finally:
            self.in_flight -= 1

    async def pooled(self, fn: Callable[[], T]) -> T:
        """`fn()` in the thread pool, whatever the load (for calls that may take long)."""
        self.in_flight += 1
        try:
            return await run_in_threadpool(self._noted, fn)
        finally:
            self.in_flight -= 1

    def _noted(self, fn: Callable[[], T]) -> T:
        try:
            result = fn()
        except BaseException:
            self.last_ok = False
            raise
        self.last_ok = True
        return result
