"""The one place the application layer gets its stores: reads through `reader`, writes through
`writer`, and, for long-lived servers, one `StoreHandle` per process that survives a restart of
the embedded store.

Reads go through the store's read-only path (`Settings.reader()`: the embedded store's reader
user, or with --uri the --read-user in READ transactions); a settings object without `reader`
gets its normal store. Every read in `app/` and the servers comes through `reader`, so the read
path is chosen in this file only.
"""
from __future__ import annotations

import threading
from pathlib import Path
from typing import Any, Callable, Optional, Protocol, TypeVar

from sg3d.graphdb.protocol import GraphStore

T = TypeVar("T")


class StoreSource(Protocol):
    """What gives the front ends their store (`sg3d.settings.Settings`, or a test's holder of one)."""

    def store(self) -> GraphStore: ...


def reader(settings: StoreSource) -> GraphStore:
    """The store for reads: the read-only user where the settings offer one."""
    return settings.reader() if hasattr(settings, "reader") else settings.store()


def writer(settings: StoreSource) -> GraphStore:
    """The store for writes (ingest)."""
    return settings.store()


def _forget_cached(settings: StoreSource) -> None:
    """Drop the settings' cached stores so the next call re-reads the daemon's server.json (a
    restarted embedded store listens on new ports) and opens a new driver."""
    for name in ("store", "reader"):
        clear = getattr(getattr(type(settings), name, None), "cache_clear", None)
        if clear is not None:
            clear()


class StoreHandle:
    """One reader and one writer Store (each a driver with its own connection pool) shared by
    every request of a server process, thread-safe.

    A request that finds the store gone (ServiceUnavailable / SessionExpired: the embedded
    daemon was stopped or restarted) gets one retry on a Store rebuilt the normal way, which
    starts the embedded store on demand or finds it on its new ports. For the embedded store the
    daemon's server.json is also watched: when it changes, the Stores are rebuilt before the
    request instead of after a failed one (the driver would otherwise retry the old port for up
    to its retry time)."""

    def __init__(self, settings: Any):   # sg3d.settings.Settings (a front end: not imported here)
        self.settings = settings
        self._lock = threading.Lock()
        self._stores: dict[str, GraphStore] = {}
        self._stamp = self._server_stamp()
        self._stopped_path: Optional[Path] = None

    def _server_stamp(self) -> Optional[tuple]:
        if not getattr(self.settings, "embedded", False):
            return None
        try:
            st = (self.settings.embedded_home() / "server.json").stat()
            return (st.st_mtime_ns, st.st_size)
        except OSError:
            return None

    def _check_not_stopped(self) -> None:
        """StoreStopped after an explicit `sg3d db stop`: a service must not undo it."""
        if not getattr(self.settings, "embedded", False):
            return
        from sg3d.graphdb.embedded import STOPPED_FILE, StoreStopped, store_dir

        if self._stopped_path is None:
            self._stopped_path = store_dir(Path(self.settings.embedded_home()).expanduser().resolve()) / STOPPED_FILE
        if self._stopped_path.exists():
            raise StoreStopped("the store was stopped; `sg3d db start`")

    def get(self, write: bool = False) -> GraphStore:
        kind = "writer" if write else "reader"
        self._check_not_stopped()
        with self._lock:
            stamp = self._server_stamp()
            if stamp != self._stamp and self._stores:
                self._drop()
            self._stamp = stamp
            if kind not in self._stores:
                self._stores[kind] = writer(self.settings) if write else reader(self.settings)
                self._stamp = self._server_stamp()
            return self._stores[kind]

    def _drop(self) -> None:
        unique = {id(s): s for s in self._stores.values()}.values()   # reader may be the writer
        for store in unique:
            try:
                store.close()
            except Exception:  # noqa: BLE001 - a dead driver may fail to close; it is dropped anyway
                pass
        self._stores.clear()
        _forget_cached(self.settings)

    def reset(self, failed) -> None:
        """Forget `failed` (and its sibling) unless another thread has already replaced it."""
        with self._lock:
            if failed in self._stores.values():
                self._drop()

    def call(self, fn: Callable[[GraphStore], T], write: bool = False) -> T:
        """`fn(store)`, retried once on a rebuilt Store when the store was unreachable."""
        from neo4j.exceptions import ServiceUnavailable, SessionExpired

        store = self.get(write)
        try:
            return fn(store)
        except (ServiceUnavailable, SessionExpired):
            self.reset(store)
            return fn(self.get(write))

    def close(self) -> None:
        with self._lock:
            self._drop()


def disk_check(settings: Any) -> Optional[Callable[[], Optional[str]]]:
    """For the embedded store: a check that says 'the disk holding ... is full' when its disk has
    less free space than SG3D_MIN_FREE_MB (read at every call), else None; None for a --uri store
    (its disk is the server's)."""
    if not getattr(settings, "embedded", False):
        return None
    from sg3d.graphdb.embedded import disk_full_message, store_dir

    folder = store_dir(Path(settings.embedded_home()).expanduser().resolve())
    return lambda: disk_full_message(folder)
