"""One writer per room: a lease kept in the graph store itself, so it holds across processes and
machines that share the store.

A build, a live map and an ingest each take the room's lease before they write and give it back
when they are done; a second writer of the room is refused (`LeaseHeld`, naming the holder) or
waits for it. The lease is a node (:Lease {room}) holding the writer's token, kind, a description,
its process id and host, and an expiry; it is taken and renewed inside write transactions whose
first statement writes the lease node (cypher/lease_touch), so two writers taking it at once
conflict and the store runs the loser again after the winner. A long writer renews it on a thread
every `LEASE_TTL_S / 3`; each of its writing transactions first checks that the lease is still its
own (`RoomLease.fence`), so a writer that lost its lease (paused past the expiry) writes nothing.

A lease whose holder died is taken over: it expired, or its process is gone from this host
(kill -9 leaves the node; the next writer on the host sees the pid is gone at once).
"""
from __future__ import annotations

import logging
import os
import socket
import threading
import time
import uuid
import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional

from sg3d.core.errors import Sg3dError
from neo4j import ManagedTransaction

from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore
from sg3d.graphdb.values import room_id

log = logging.getLogger("sg3d.lease")

# A holder renews every third of this; a holder that stopped renewing (a machine that went away)
# is taken over after it. Long enough that a busy machine's renewal thread is never late.
LEASE_TTL_S = 60.0
# How often a writer that waits (`--wait`) asks again.
WAIT_POLL_S = 0.5

_schema_done: "weakref.WeakSet" = weakref.WeakSet()
# Tokens of the leases this process holds now: one of its own it no longer holds (a release the
# store refused, on a full disk) is free at once, not at its expiry.
_held_here: set[str] = set()


class LeaseHeld(Sg3dError, RuntimeError):
    """Another writer holds the room (the message names it, on one line)."""

    def __init__(self, room: str, holder: "Holder"):
        self.room, self.holder = room, holder
        super().__init__(f"room {room} is being written by {holder.describe()}; "
                         f"wait for it to finish (or give --wait)")


class LeaseLost(Sg3dError, RuntimeError):
    """This writer's lease went to another writer (it stopped renewing past the expiry)."""


@dataclass(frozen=True)
class Holder:
    token: str
    kind: str
    holder: str
    pid: int
    host: str
    since: float
    expires: float

    @classmethod
    def of(cls, row: dict) -> Optional["Holder"]:
        if not row or row.get("token") is None:
            return None
        return cls(str(row["token"]), str(row.get("kind") or "?"), str(row.get("holder") or "?"),
                   int(row.get("pid") or 0), str(row.get("host") or "?"), float(row.get("since") or 0.0),
                   float(row.get("expires") or 0.0))

    def describe(self) -> str:
        since = time.strftime("%H:%M:%S", time.localtime(self.since))
        return f"{self.kind} '{self.holder}' (pid {self.pid} on {self.host}, since {since})"


def pid_alive(pid: int) -> bool:
    """Whether process `pid` runs on this host (a zombie, killed and not yet reaped, does not)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    return stat.rsplit(")", 1)[-1].split()[:1] != ["Z"]


def holder_gone(h: Holder, now: float, host: str) -> bool:
    """Rule "a dead holder's lease is free": it expired, or its process is gone from this host, or
    it is this process's and this process let it go."""
    if h.expires < now:
        return True
    if h.host != host:
        return False
    if h.pid == os.getpid():
        return h.token not in _held_here
    return not pid_alive(h.pid)


class RoomLease:
    """The lease of one room for one writer (`take`, `release`, or `with lease.held(...)`)."""

    def __init__(self, store: GraphStore, building: str, room: str, kind: str, holder: str,
                 ttl: float = LEASE_TTL_S) -> None:
        self.store, self.building, self.room = store, building, room
        self.rid = room_id(building, room)
        self.kind, self.holder, self.ttl = kind, holder[:200], ttl
        self.token = uuid.uuid4().hex
        self.pid, self.host = os.getpid(), socket.gethostname()
        self.since = 0.0
        self.lost = False
        self._stop = threading.Event()
        self._thread: Optional[threading.Thread] = None

    # -- taking ---------------------------------------------------------------------------------
    def _ensure(self) -> None:
        from neo4j.exceptions import ConstraintError

        if self.store not in _schema_done:
            with self.store.session() as s:
                s.run(cypher.load("lease_schema")).consume()
            _schema_done.add(self.store)
        for attempt in range(4):
            try:
                self.store.write("lease_ensure", room=self.rid)
                return
            except ConstraintError:   # another writer created it first: it is there now
                time.sleep(0.05 * (attempt + 1))

    def _take_in_tx(self, tx: ManagedTransaction) -> Optional[Holder]:
        """One try: the holder that keeps the lease, or None when this writer has it now."""
        row = tx.run(cypher.load("lease_touch"), room=self.rid).single()
        if row is None:
            raise _NoLeaseNode()
        now = time.time()
        current = Holder.of(dict(row))
        if current is not None and current.token != self.token and not holder_gone(current, now, self.host):
            return current
        if current is None or current.token != self.token:
            self.since = now
        tx.run(cypher.load("lease_set"), room=self.rid, token=self.token, kind=self.kind, holder=self.holder,
               pid=self.pid, host=self.host, since=self.since, expires=now + self.ttl).consume()
        return None

    def try_take(self) -> Optional[Holder]:
        """Take the lease if it is free (or its holder died); the holder otherwise."""
        for _ in range(5):
            self._ensure()
            try:
                return self.store.execute_write(self._take_in_tx)
            except _NoLeaseNode:     # released (deleted) between ensure and take: again
                continue
        raise LeaseLost(f"could not take the lease of room {self.rid}: it kept changing hands")

    def take(self, wait: Callable[[Holder], bool] = lambda h: False, poll: float = WAIT_POLL_S,
             deadline: Optional[float] = None) -> None:
        """Take the lease, or LeaseHeld; while `wait(holder)` says so (and before `deadline`, a
        time.monotonic), ask again every `poll` seconds. Starts the renewal thread."""
        said = False
        while True:
            holder = self.try_take()
            if holder is None:
                break
            if not wait(holder) or (deadline is not None and time.monotonic() >= deadline):
                raise LeaseHeld(self.rid, holder)
            if not said and self.kind != "ingest":
                log.warning("room %s is being written by %s; waiting for it", self.rid, holder.describe())
                said = True
            time.sleep(poll)
        _held_here.add(self.token)
        self._thread = threading.Thread(target=self._renew_loop, name="sg3d-lease", daemon=True)
        self._thread.start()

    # -- holding --------------------------------------------------------------------------------
    def _renew_loop(self) -> None:
        while not self._stop.wait(self.ttl / 3):
            try:
                holder = self.store.execute_write(self._take_in_tx)
            except Exception:  # noqa: BLE001 - a store briefly away: the next turn tries again
                continue
            if holder is not None:
                self.lost = True
                return

    def fence(self, tx: ManagedTransaction) -> None:
        """Inside a writing transaction of the holder: LeaseLost unless the lease is still its own
        (the transaction then rolls back: a writer that lost the room writes nothing)."""
        row = tx.run(cypher.load("lease_get"), room=self.rid).single()
        current = Holder.of(dict(row)) if row is not None else None
        if current is None or current.token != self.token:
            other = f"it is now {current.describe()}'s" if current is not None else "it was released"
            raise LeaseLost(f"this {self.kind} lost the lease of room {self.rid} ({other}); nothing more was written")

    def release(self) -> None:
        """Stop renewing and give the lease back (best effort: an expired lease frees itself)."""
        self._stop.set()
        _held_here.discard(self.token)
        if self._thread is not None:
            self._thread.join(timeout=5)
        try:
            self.store.write("lease_release", room=self.rid, token=self.token)
        except Exception:  # noqa: BLE001 - the writer's own outcome is what the caller must see
            log.debug("could not release the lease of %s", self.rid, exc_info=True)

    def __enter__(self) -> "RoomLease":
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()


class _NoLeaseNode(Sg3dError):
    """The lease node went between ensuring it and taking it (a holder released it)."""
