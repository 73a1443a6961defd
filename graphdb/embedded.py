"""The embedded store as a local daemon: ArcadeDB with its Bolt plugin on loopback.

Files under the home directory:
    server.lock   held (flock) by the running daemon for its whole life: the one source of
                  truth for "is it running". A crash releases it, so a stale pid is recognised
                  without guessing from pids.
    start.lock    held by whoever is starting the daemon, so two sg3d commands at once
                  start one server, not two.
    server.json   pid, ports and database of the running daemon (written when it is ready).
    password      generated root password, mode 0600 (sg3d never logs in as root).
    users.json    sg3d's two store users, mode 0600: the writer (build, merge, --write) and the
                  reader, whose group may only read records (every read-only path). Their names
                  carry a random suffix: ArcadeDB locks a user name out for a while after repeated
                  failed logins, and a process that cannot read this file cannot name them.
    server.log    the daemon's output.
    databases/    ArcadeDB's data.
"""
from __future__ import annotations

import fcntl
import json
import os
import secrets
import signal
import socket
import subprocess
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Optional

DATABASE = "sg3d"
ROOT_USER = "root"
WRITER_GROUP = "sg3d_writer"
READER_GROUP = "sg3d_reader"
START_TIMEOUT_S = float(os.environ.get("SG3D_START_TIMEOUT", "90"))
STOP_TIMEOUT_S = 30.0


class EmbeddedStoreError(RuntimeError):
    pass


def default_home() -> Path:
    env = os.environ.get("SG3D_HOME")
    if env:
        return Path(env).expanduser()
    from platformdirs import user_data_dir

    return Path(user_data_dir("sg3d", appauthor=False))


@dataclass(frozen=True)
class Credentials:
    """sg3d's two store users (users.json)."""

    writer: str
    writer_password: str
    reader: str
    reader_password: str


@dataclass(frozen=True)
class ServerInfo:
    pid: int
    bolt_port: int
    http_port: int
    database: str
    started_at: float
    credentials: Credentials

    @property
    def uri(self) -> str:
        return f"bolt://127.0.0.1:{self.bolt_port}"

    @property
    def user(self) -> str:
        """The writer's name (build, merge, schema, --write)."""
        return self.credentials.writer

    @property
    def password(self) -> str:
        return self.credentials.writer_password

    @property
    def writer_auth(self) -> tuple[str, str]:
        return self.credentials.writer, self.credentials.writer_password

    @property
    def reader_auth(self) -> tuple[str, str]:
        return self.credentials.reader, self.credentials.reader_password


@dataclass(frozen=True)
class Status:
    running: bool
    info: Optional[ServerInfo] = None
    recovered_stale: bool = False  # a dead daemon's leftovers were found and cleared


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def port_open(port: int, timeout: float = 0.5) -> bool:
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=timeout):
            return True
    except OSError:
        return False


@contextmanager
def _flock(path: Path, blocking: bool, timeout: float = 0.0) -> Iterator[bool]:
    """Yield True if the exclusive lock on `path` was taken (released on exit)."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        deadline = time.monotonic() + timeout
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                got = True
                break
            except BlockingIOError:
                if not blocking or time.monotonic() > deadline:
                    got = False
                    break
                time.sleep(0.05)
        try:
            yield got
        finally:
            if got:
                fcntl.flock(fd, fcntl.LOCK_UN)
    finally:
        os.close(fd)


class EmbeddedServer:
    """Start, find, and stop the embedded store daemon of one home directory."""

    def __init__(self, home: Path | str):
        self.home = Path(home).expanduser().resolve()

    # -- files ---------------------------------------------------------------------------
    @property
    def info_path(self) -> Path:
        return self.home / "server.json"

    @property
    def lock_path(self) -> Path:
        return self.home / "server.lock"

    @property
    def log_path(self) -> Path:
        return self.home / "server.log"

    @property
    def users_path(self) -> Path:
        return self.home / "users.json"

    def _secret_file(self, path: Path, make) -> str:
        """A generated secret kept in a file only the user can read (created once, race-free)."""
        if not path.exists():
            try:
                fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            except FileExistsError:
                pass  # another sg3d made it a moment ago
            else:
                with os.fdopen(fd, "w") as f:
                    f.write(make())
        os.chmod(path, 0o600)
        text = path.read_text().strip()
        if not text:  # the other writer has not finished yet
            time.sleep(0.05)
            text = path.read_text().strip()
        return text

    def password(self) -> str:
        """The root password (ArcadeDB's administrator; sg3d itself logs in as its own users)."""
        return self._secret_file(self.home / "password", lambda: secrets.token_urlsafe(24))

    def credentials(self) -> Credentials:
        """sg3d's writer and reader users, generated once (users.json, mode 0600)."""
        def make() -> str:
            tag = secrets.token_hex(4)
            return json.dumps({"writer": f"sg3d_writer_{tag}", "writer_password": secrets.token_urlsafe(24),
                               "reader": f"sg3d_reader_{tag}", "reader_password": secrets.token_urlsafe(24)})
        try:
            return Credentials(**json.loads(self._secret_file(self.users_path, make)))
        except (ValueError, TypeError) as exc:
            raise EmbeddedStoreError(
                f"{self.users_path} is damaged ({exc}); delete it and run `sg3d db stop`: the next start "
                f"creates new store users") from None

    def _read_info(self) -> Optional[ServerInfo]:
        try:
            data = json.loads(self.info_path.read_text())
            return ServerInfo(credentials=self.credentials(), **data)
        except (OSError, ValueError, TypeError):
            return None

    # -- state ---------------------------------------------------------------------------
    def status(self) -> Status:
        if not self.home.exists():
            return Status(False)
        with _flock(self.lock_path, blocking=False) as free:
            if free:
                # Nobody holds the daemon lock: whatever server.json says is left from a crash.
                stale = self.info_path.exists()
                if stale:
                    self.info_path.unlink(missing_ok=True)
                return Status(False, recovered_stale=stale)
        info = self._read_info()
        if info is None:
            return Status(True)  # starting: lock held, not ready yet
        return Status(True, info)

    def ensure_running(self) -> ServerInfo:
        """Return the running daemon's info, starting it first if needed."""
        st = self.status()
        if st.running and st.info is not None:
            return st.info
        return self.start()

    def start(self) -> ServerInfo:
        self.home.mkdir(parents=True, exist_ok=True)
        os.chmod(self.home, 0o700)
        with _flock(self.home / "start.lock", blocking=True, timeout=START_TIMEOUT_S) as got:
            if not got:
                raise EmbeddedStoreError(f"another sg3d is still starting the store in {self.home}")
            st = self.status()
            if st.running:
                return st.info or self._wait_ready(None)
            self.password()
            self.credentials()
            log = open(self.log_path, "ab")
            env = dict(os.environ)
            proc = subprocess.Popen(
                [sys.executable, "-m", "graphdb.daemon", str(self.home)],
                stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                cwd=self.home, start_new_session=True, env=env,
            )
            log.close()
            return self._wait_ready(proc)

    def _wait_ready(self, proc: Optional[subprocess.Popen]) -> ServerInfo:
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline:
            if proc is not None and proc.poll() is not None:
                raise EmbeddedStoreError(
                    f"the embedded store exited during start-up (code {proc.returncode}); "
                    f"last log lines:\n{self._log_tail()}")
            info = self._read_info()
            if info is not None and port_open(info.bolt_port):
                return info
            time.sleep(0.1)
        if proc is not None:
            proc.kill()
        raise EmbeddedStoreError(
            f"the embedded store did not start within {START_TIMEOUT_S:.0f} s; see {self.log_path}")

    def stop(self) -> bool:
        """Stop the daemon; False if it was not running."""
        st = self.status()
        if not st.running:
            return False
        pid = st.info.pid if st.info else self._pid_from_file()
        if pid:
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + STOP_TIMEOUT_S
        while time.monotonic() < deadline:
            if not self.status().running:
                return True
            time.sleep(0.1)
        if pid:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        time.sleep(0.5)
        self.status()  # clears the leftovers of the killed daemon
        return True

    def _pid_from_file(self) -> Optional[int]:
        try:
            return int(json.loads(self.info_path.read_text())["pid"])
        except (OSError, ValueError, KeyError):
            return None

    def _log_tail(self, n: int = 15) -> str:
        try:
            return "\n".join(self.log_path.read_text(errors="replace").splitlines()[-n:])
        except OSError:
            return "(no log)"
