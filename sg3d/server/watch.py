"""Whether the store is up, known without the driver (which retries a dead store's port for its
whole retry time): for the embedded store, from the daemon's own files; for a --uri store, from a
TCP connection to its address.

States: "up"; "down" (not answering: killed, crashed, starting); "stopped" (an explicit
`sg3d db stop`, which a service must not undo); "unknown" (a --uri store when no probe was asked).
When the embedded store is down and was not stopped, `StoreWatch` restarts it in the background,
once at a time (what a CLI command would do on demand), while requests get 503 + Retry-After.
"""
from __future__ import annotations

import json
import logging
import socket
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Optional
from urllib.parse import urlsplit

from sg3d.server.dispatch import StoreUnavailable

if TYPE_CHECKING:
    from sg3d.settings import Settings

log = logging.getLogger("sg3d.serve")

UP, DOWN, STOPPED, UNKNOWN = "up", "down", "stopped", "unknown"
STATE_TTL_S = 0.2          # a state read is reused this long (two small file reads otherwise)
# longer than TCP's first SYN retransmission (1 s): a connection attempt the store's full accept queue
# dropped once is retried by the kernel, not read as a store that is down
PROBE_TIMEOUT_S = 1.5
DOWN_DETAIL = "the graph store is unreachable or restarting; retry shortly"
STOPPED_DETAIL = "the store was stopped; `sg3d db start`"


class StoreWatch:
    """The state of `settings`' store; `restart` (run in a daemon thread) brings a dead embedded
    store back."""

    def __init__(self, settings: Settings, restart: Optional[Callable[[], None]] = None):
        self.embedded = bool(getattr(settings, "embedded", False))
        self._restart_fn = restart
        self._restarting = threading.Lock()
        self._cached: tuple[float, str] = (0.0, UNKNOWN)
        self._probing = threading.Lock()
        self._probed: tuple[float, str] = (0.0, UNKNOWN)   # when the last probe ended, and what it found
        self.last_restart_error: Optional[str] = None
        if self.embedded:
            from sg3d.graphdb.embedded import STOPPED_FILE, store_dir

            home = store_dir(Path(settings.embedded_home()).expanduser().resolve())
            self._info_path, self._stopped_path = home / "server.json", home / STOPPED_FILE
            self._address: Optional[tuple[str, int]] = None
        else:
            parts = urlsplit(getattr(settings, "uri", None) or "")
            self._address = (parts.hostname, parts.port or 7687) if parts.hostname else None

    # -- the state -------------------------------------------------------------------------
    def state(self, probe: bool = False) -> str:
        """The store's state. `probe`: also connect to its Bolt port (else an embedded daemon
        counts as up while its process lives, and a --uri store is "unknown")."""
        now = time.monotonic()
        if not probe:
            if now - self._cached[0] < STATE_TTL_S:
                return self._cached[1]
            state = self._embedded_state(False) if self.embedded else self._remote_state(False)
            self._cached = (now, state)
            return state
        # One probe at a time, and a caller that waited for another's takes its answer (it ended
        # after this caller asked): a burst of /health probing at once overflowed the store's
        # accept queue, read it as down, and restarted the connections under every other call.
        with self._probing:
            if self._probed[0] >= now:
                return self._probed[1]
            state = self._embedded_state(True) if self.embedded else self._remote_state(True)
            self._probed = self._cached = (time.monotonic(), state)
        return state

    def _embedded_state(self, probe: bool) -> str:
        from sg3d.graphdb.embedded import port_open, process_alive

        if self._stopped_path.exists():
            return STOPPED
        try:
            info = json.loads(self._info_path.read_text())
            pid, port = int(info["pid"]), int(info["bolt_port"])
        except (OSError, ValueError, KeyError, TypeError):
            return DOWN          # no daemon, or one still starting (it writes server.json when ready)
        if not process_alive(pid):
            return DOWN
        if probe and not port_open(port, PROBE_TIMEOUT_S):
            return DOWN
        return UP

    def _remote_state(self, probe: bool) -> str:
        if not probe or self._address is None:
            return UNKNOWN
        try:
            with socket.create_connection(self._address, timeout=PROBE_TIMEOUT_S):
                return UP
        except OSError:
            return DOWN

    def raise_if_down(self, probe: bool = False) -> None:
        """StoreStopped after an explicit stop, StoreUnavailable (restart begun) when down."""
        state = self.state(probe)
        if state == STOPPED:
            from sg3d.graphdb.embedded import StoreStopped

            raise StoreStopped(STOPPED_DETAIL)
        if state == DOWN:
            self.restart()
            raise StoreUnavailable(DOWN_DETAIL)

    # -- bringing it back ------------------------------------------------------------------
    def restart(self) -> None:
        """Restart a dead embedded store in a daemon thread, unless one is restarting it already."""
        if not self.embedded or self._restart_fn is None or not self._restarting.acquire(blocking=False):
            return
        threading.Thread(target=self._restart, name="sg3d-store-restart", daemon=True).start()

    def _restart(self) -> None:
        try:
            if self._restart_fn is not None:
                self._restart_fn()
            self.last_restart_error = None
        except Exception as exc:  # noqa: BLE001 - the next request tries again; the reason is logged
            self.last_restart_error = f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
            log.warning("restarting the store failed: %s", self.last_restart_error)
        finally:
            self._cached = (0.0, UNKNOWN)
            self._restarting.release()
