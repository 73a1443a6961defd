"""The fast lane's guard: while a unit test runs, an audit hook turns starting a process,
connecting a socket (Bolt, HTTP) or opening a file under ../shared into a `LaneError`."""
from __future__ import annotations

import os
import sys

from tests.conftest import SHARED

PROCESS_EVENTS = frozenset({"subprocess.Popen", "os.system", "os.posix_spawn", "os.spawn", "os.exec",
                            "os.fork", "os.forkpty"})
SHARED_PREFIX = os.path.abspath(SHARED) + os.sep


class LaneError(RuntimeError):
    """A unit test reached for a process, the network or the shared data."""


class _Lane:
    guarded = False


def lane_audit(event: str, args: tuple) -> None:
    """Refuse what a unit test may not do; audit hooks cannot be removed, so the hook stays
    installed and only acts while a unit test runs."""
    if not _Lane.guarded:
        return
    if event in PROCESS_EVENTS:
        raise LaneError(f"a unit test started a process ({event}): move it out of tests/unit")
    if event == "socket.connect":
        raise LaneError(f"a unit test opened a connection to {args[1]!r}: move it out of tests/unit")
    if event == "open" and isinstance(args[0], (str, bytes, os.PathLike)):
        path = os.path.abspath(os.fsdecode(args[0]))
        if path.startswith(SHARED_PREFIX):
            raise LaneError(f"a unit test read the shared data ({path}): move it out of tests/unit")


def install() -> None:
    sys.addaudithook(lane_audit)


def guard(on: bool) -> None:
    _Lane.guarded = on
