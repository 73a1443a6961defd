"""One writer per room: every front end's writes (build, live map, ingest) go through `writing`,
which holds the room's lease (`sg3d.graphdb.lease`) for the whole write and turns a refusal into
the caller's one-line error (the CLI's exit 2, HTTP 409)."""
from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Callable, Iterator, Optional, Union

from sg3d.app.errors import RoomBusy
from sg3d.graphdb.lease import Holder, LeaseHeld, LeaseLost, RoomLease
from sg3d.graphdb.protocol import GraphStore

# An ingest is one transaction: one waits this long for another ingest of its room (a build or a
# live map holds the room for minutes, so an ingest is refused at once while they write).
INGEST_WAIT_S = 10.0
INGEST_POLL_S = 0.05


@contextmanager
def writing(store: GraphStore, building: str, room: str, kind: str, holder: str,
            wait: Union[bool, Callable[[Holder], bool]] = False, wait_s: Optional[float] = None,
            error: type[Exception] = RoomBusy) -> Iterator[RoomLease]:
    """Hold room `building/room`'s lease while the block writes (`RoomLease.fence` for each of its
    transactions); `error` (one line naming the holder) when another writer holds it, after
    waiting for it while `wait` says so (at most `wait_s` seconds when given). A lease lost
    mid-way is `error` too."""
    lease = RoomLease(store, building, room, kind, holder)
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
