"""Where a route runs its application-layer call: never on the event loop, always with a deadline.

The application layer and the store driver are synchronous, and a driver call can wait a long
time (it retries a dead store's port for its whole retry time) or, after a broken exchange with
the store, forever. So every call runs in a worker thread (`CallThreads`) while the event loop awaits
it with a deadline, checking the store's state (`sg3d.server.watch.StoreWatch`) a few times a
second: a store that is down, or a call past its deadline, is answered at once with
`StoreUnavailable` (503 with Retry-After), and the worker is left to finish on its own. The
event loop is never held, so /health answers and SIGTERM stops the server whatever the store does.

`CallThreads` is a kept pool: a fixed number of threads (`MAX_THREADS`, `sg3d serve --threads`) on one
standard queue, started as calls need them and never ended while the process runs, so no idle
timeout can leave a queued call without a thread. Two promises shape it, and neither the standard
library's pools nor anyio's keep both, which is why it is not `concurrent.futures.ThreadPoolExecutor`
or `anyio.to_thread`:
- its threads are daemon threads: the interpreter joins ThreadPoolExecutor's and anyio's at exit,
  so one stuck in a store call would keep a stopped server's process alive;
- a call given up on (its deadline passed, or the store went down) stops counting against the pool:
  while it still runs, a replacement thread takes its place, and its own thread ends when it
  returns, so stuck calls never starve new ones (a fixed executor would lose a thread to each).
"""
from __future__ import annotations

import asyncio
import concurrent.futures
import threading
from queue import SimpleQueue
from typing import Awaitable, Callable, Generic, Optional, TypeVar

from sg3d.app.bounds import DEFAULT_THREADS
from sg3d.core.errors import Sg3dError

T = TypeVar("T")

QUICK_TIMEOUT_S = 30.0     # a read (/ask, /rooms, objects): the embedded store stops a statement after 30 s
LONG_TIMEOUT_S = 300.0     # a plan, an export, an ingest
POLL_S = 0.25              # how often a waiting call looks at the store's state
RETRY_AFTER_S = 2
MAX_THREADS = DEFAULT_THREADS   # threads running calls at once (stuck ones not counted)


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


class CallThreads:
    """A kept pool of `size` daemon threads on one queue (see the module's docstring). Threads start
    as calls need them, up to `size` not counting stuck ones, and are never ended for being idle; a
    thread whose call was abandoned while it ran (`abandon`) is replaced at once and ends when
    that call returns. The counts are exact, under one lock: `_queued` calls not yet taken by a
    thread, `_waiting` threads blocked on the queue; a call starts a thread when the queued calls
    outnumber the waiting threads."""

    def __init__(self, size: int = MAX_THREADS):
        if size < 1:
            raise ValueError("a worker pool needs at least one thread")
        self.size = size
        self._jobs: SimpleQueue[_Job] = SimpleQueue()
        self._lock = threading.Lock()
        self._threads = 0
        self._stuck = 0
        self._queued = 0
        self._waiting = 0

    def submit(self, fn: Callable[[], T]) -> _Job:
        job = _Job(fn)
        with self._lock:
            self._queued += 1
            self._jobs.put(job)
            self._grow()
        return job

    def abandon(self, job: _Job) -> None:
        """The caller stopped waiting for `job`: one not started never runs; one running has its
        thread counted stuck (and replaced, when calls are queued) until it returns."""
        if job.future.cancel():
            return
        with self._lock:
            if not job.finished and not job.abandoned:
                job.abandoned = True
                self._stuck += 1
                self._grow()

    def _grow(self) -> None:
        """Under the lock: one more thread when a queued call has no waiting thread and the pool
        has fewer than `size` threads that are not stuck."""
        if self._queued > self._waiting and self._threads - self._stuck < self.size:
            self._threads += 1
            threading.Thread(target=self._work, name="sg3d-call", daemon=True).start()

    def _work(self) -> None:
        while True:
            with self._lock:
                self._waiting += 1
            job = self._jobs.get()
            with self._lock:
                self._waiting -= 1
                self._queued -= 1
            if not job.future.set_running_or_notify_cancel():
                continue
            result, error = None, None
            try:
                result = job.fn()
            except BaseException as exc:  # noqa: BLE001 - handed to the awaiting request
                error = exc
            with self._lock:
                job.finished = True
                surplus = job.abandoned and self._threads - (self._stuck - 1) > self.size
                if job.abandoned:
                    self._stuck -= 1
                if surplus:               # a replacement took this thread's place while it was stuck
                    self._threads -= 1
            if error is not None:
                job.future.set_exception(error)
            else:
                job.future.set_result(result)
            if surplus:
                return


class Dispatcher:
    """Runs each route's call in `CallThreads` with a deadline, refusing it at once while `watch`
    says the store is down. `in_flight` counts the calls being awaited."""

    def __init__(self, watch=None, threads: Optional[CallThreads] = None,
                 quick_timeout_s: float = QUICK_TIMEOUT_S, long_timeout_s: float = LONG_TIMEOUT_S):
        self.watch = watch
        self.threads = threads or CallThreads()
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
            job = self.threads.submit(fn)
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
        self.threads.abandon(job)
        # the call's eventual exception is nobody's: read it so asyncio does not log it
        waiting.add_done_callback(lambda f: f.cancelled() or f.exception())


class SharedRead(Generic[T]):
    """One call (`run`, awaited on the event loop: a `Dispatcher` call, with its deadline and its
    503 while the store is down) shared by the requests that arrive together. Rule "a read that
    began after the request arrived", as `sg3d.app.answers.Revisions` keeps it for threads: a
    request that finds no read running starts one; one that arrives while a read runs waits for
    the next read, which starts as soon as the running one ends. So every request gets a result
    begun after it arrived, and a crowd's requests cost one worker-thread hop per read, not one
    each (the event loop runs this class alone: no lock)."""

    def __init__(self, run: Callable[[], Awaitable[T]]):
        self._run = run
        self._running: Optional[asyncio.Future] = None
        self._next: Optional[asyncio.Future] = None
        self.reads = 0

    async def get(self) -> T:
        if self._running is None:
            shared = self._start()
        else:
            if self._next is None:
                self._next = asyncio.get_running_loop().create_future()
                self._next.add_done_callback(_retrieved)
            shared = self._next
        return await asyncio.shield(shared)     # a request that goes away leaves the read to the others

    def _start(self) -> asyncio.Future:
        self.reads += 1
        task = asyncio.ensure_future(self._run())
        task.add_done_callback(self._ended)
        self._running = task
        return task

    def _ended(self, task: asyncio.Future) -> None:
        _retrieved(task)
        self._running = None
        waiting, self._next = self._next, None
        if waiting is not None:
            self._start().add_done_callback(lambda done: _hand_over(done, waiting))


def _retrieved(future: asyncio.Future) -> None:
    """Read a shared future's exception: every request waiting on it has it raised; when none is
    left, asyncio must not log it as never retrieved."""
    if not future.cancelled():
        future.exception()


def _hand_over(done: asyncio.Future, waiting: asyncio.Future) -> None:
    if waiting.done():
        return
    if done.cancelled():
        waiting.cancel()
    elif done.exception() is not None:
        waiting.set_exception(done.exception())     # type: ignore[arg-type]
    else:
        waiting.set_result(done.result())
