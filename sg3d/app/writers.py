"""One writer per room: every front end's writes (build, live map, ingest) go through `writing`,
which holds the room's lease (`sg3d.graphdb.lease`) for the whole write and turns a refusal into
the caller's one-line error (the CLI's exit 2, HTTP 409)."""
from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Iterator, Optional, Union

from sg3d.app.errors import RoomBusy
from sg3d.graphdb.lease import Holder, LeaseHeld, LeaseLost, RoomLease
from sg3d.graphdb.protocol import GraphStore

# An ingest is one transaction: one waits this long for another ingest of its room (a build or a
# live map holds the room for minutes, so an ingest is refused at once while they write).
INGEST_WAIT_S = 10.0
INGEST_POLL_S = 0.05


@dataclass(frozen=True)
class Writer:
    """Who writes a room (`kind`: build, map or ingest; `holder`: what the lease shows others) and
    whether it waits for another writer (`wait`: always, never, or by the holder; at most `wait_s`
    seconds when given)."""

    kind: str
    holder: str
    wait: Union[bool, Callable[[Holder], bool]] = False
    wait_s: Optional[float] = None


@contextmanager
def writing(store: GraphStore, building: str, room: str, writer: Writer,
            error: type[Exception] = RoomBusy) -> Iterator[RoomLease]:
    """Hold room `building/room`'s lease while the block writes (`RoomLease.fence` for each of its
    transactions); `error` (one line naming the holder) when another writer holds it, after
    waiting for it while `writer.wait` says so. A lease lost mid-way is `error` too."""
    kind, wait, wait_s = writer.kind, writer.wait, writer.wait_s
    lease = RoomLease(store, building, room, kind, writer.holder)
    should_wait = wait if callable(wait) else (lambda h: bool(wait))
    deadline = None if wait_s is None else time.monotonic() + wait_s
    try:
        lease.take(should_wait, poll=INGEST_POLL_S if kind == "ingest" else 0.5, deadline=deadline)
    except (LeaseHeld, LeaseLost) as exc:
        raise error(str(exc)) from None
    try:
        yield lease
    except LeaseLost as exc:
        raise error(str(exc)) from None
    finally:
        lease.release()
