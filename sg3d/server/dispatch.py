"""Where a route runs its application-layer call: never on the event loop, always with a deadline.

The application layer and the store driver are synchronous, and a driver call can wait a long
time (it retries a dead store's port for its whole retry time) or, after a broken exchange with
the store, forever. So every call runs in a worker thread (`Workers`) while the event loop awaits
it with a deadline, checking the store's state (`sg3d.server.watch.StoreWatch`) a few times a
second: a store that is down, or a call past its deadline, is answered at once with
`StoreUnavailable` (503 with Retry-After), and the worker is left to finish on its own. The
event loop is never held, so /health answers and SIGTERM stops the server whatever the store does.

The workers are daemon threads (anyio's and concurrent.futures' are not: the interpreter joins
them at exit, so one stuck in a store call would keep a stopped server's process alive).
"""
from __future__ import annotations

import asyncio
import concurrent.futures
import threading
from queue import Empty, SimpleQueue
from typing import Callable, Optional, TypeVar

from sg3d.core.errors import Sg3dError

T = TypeVar("T")

QUICK_TIMEOUT_S = 30.0     # a read (/ask, /rooms, objects): the embedded store stops a statement after 30 s
LONG_TIMEOUT_S = 300.0     # a plan, an export, an ingest
POLL_S = 0.25              # how often a waiting call looks at the store's state
RETRY_AFTER_S = 2
MAX_WORKERS = 64           # threads running calls at once (stuck ones not counted)
IDLE_S = 60.0              # an idle worker thread ends after this long


class StoreUnavailable(Sg3dError, RuntimeError):
    """The store is down or restarting, or a call passed its deadline: a 503 with Retry-After."""

    def __init__(self, detail: str, retry_after: int = RETRY_AFTER_S):
        super().__init__(detail)
        self.retry_after = retry_after


class _Job:
    __slots__ = ("fn", "future", "abandoned", "finished")

    def __init__(self, fn: Callable):
        self.fn = fn
        self.future: concurrent.futures.Future = concurrent.futures.Future()
        self.abandoned = False
        self.finished = False


class Workers:
    """A pool of daemon threads: one per call in flight up to MAX_WORKERS (idle ones are reused,
    and end after `idle_s`; further calls queue). A call the caller gave up on (`abandon`) no
    longer counts against the limit, so stuck calls cannot starve new ones. `_idle` holds one
    token per idle worker that no submitted call has claimed yet."""

    def __init__(self, limit: int = MAX_WORKERS, idle_s: float = IDLE_S):
        self.limit = limit
        self.idle_s = idle_s
        self._jobs: SimpleQueue[_Job] = SimpleQueue()
        self._idle = threading.Semaphore(0)
        self._lock = threading.Lock()
        self._threads = 0
        self._stuck = 0

    def submit(self, fn: Callable[[], T]) -> _Job:
        job = _Job(fn)
        self._jobs.put(job)
        if not self._idle.acquire(blocking=False):
            with self._lock:
                if self._threads - self._stuck < self.limit:
                    self._threads += 1
                    threading.Thread(target=self._work, name="sg3d-call", daemon=True).start()
        return job

    def abandon(self, job: _Job) -> None:
        """The caller stopped waiting for `job`: one not started never runs; one running has its
        thread counted stuck until it returns."""
        if job.future.cancel():
            return
        with self._lock:
            if not job.finished and not job.abandoned:
                job.abandoned = True
                self._stuck += 1

    def _work(self) -> None:
        while True:
            try:
                job = self._jobs.get(timeout=self.idle_s)
            except Empty:
                if self._idle.acquire(blocking=False):      # no call has claimed this worker: end
                    with self._lock:
                        self._threads -= 1
                    return
                continue                                    # one is coming
            if not job.future.set_running_or_notify_cancel():
                self._idle.release()
                continue
            result, error = None, None
            try:
                result = job.fn()
            except BaseException as exc:  # noqa: BLE001 - handed to the awaiting request
                error = exc
            with self._lock:
                job.finished = True
                if job.abandoned:
                    self._stuck -= 1
            self._idle.release()          # free before the caller hears: its next call reuses this thread
            if error is not None:
                job.future.set_exception(error)
            else:
                job.future.set_result(result)


class Dispatcher:
    """Runs each route's call in `Workers` with a deadline, refusing it at once while `watch`
    says the store is down. `in_flight` counts the calls being awaited."""

    def __init__(self, watch=None, workers: Optional[Workers] = None,
                 quick_timeout_s: float = QUICK_TIMEOUT_S, long_timeout_s: float = LONG_TIMEOUT_S):
        self.watch = watch
        self.workers = workers or Workers()
        self.quick_timeout_s = quick_timeout_s
        self.long_timeout_s = long_timeout_s
        self.in_flight = 0

    async def quick(self, fn: Callable[[], T]) -> T:
        """`fn()` for a read, within `quick_timeout_s`."""
        return await self.run(fn, self.quick_timeout_s)

    async def pooled(self, fn: Callable[[], T]) -> T:
        """`fn()` for a call that may take long (plan, export, ingest), within `long_timeout_s`."""
        return await self.run(fn, self.long_timeout_s)

    async def run(self, fn: Callable[[], T], timeout_s: float, watched: bool = True) -> T:
        """`fn()` in a worker; StoreUnavailable when the store is (or goes) down meanwhile, or
        when `timeout_s` passes. `watched=False`: no store check (for the store check itself)."""
        watch = self.watch if watched else None
        self.in_flight += 1
        try:
            if watch is not None:
                watch.raise_if_down()
            job = self.workers.submit(fn)
            waiting = asyncio.wrap_future(job.future)
            loop = asyncio.get_running_loop()
            deadline = loop.time() + timeout_s
            while True:
                left = deadline - loop.time()
                if left <= 0:
                    self._give_up(job, waiting)
                    raise StoreUnavailable(f"the graph store did not answer within {timeout_s:g} s; retry shortly")
                done, _ = await asyncio.wait({waiting}, timeout=min(POLL_S, left))
                if done:
                    return waiting.result()
                if watch is not None:
                    try:
                        watch.raise_if_down()
                    except BaseException:
                        self._give_up(job, waiting)
                        raise
        finally:
            self.in_flight -= 1

    def _give_up(self, job: _Job, waiting: asyncio.Future) -> None:
        self.workers.abandon(job)
        # the call's eventual exception is nobody's: read it so asyncio does not log it
        waiting.add_done_callback(lambda f: f.cancelled() or f.exception())
