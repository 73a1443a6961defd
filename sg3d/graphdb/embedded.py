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
    store-lost    why the daemon stopped when its database files went (`sg3d db start` clears it).
Beside the home, in its parent: `.<home name>.sg3d-database`, the record that a database was
created and which files it keeps (`sg3d.graphdb.filewatch`): it outlives the store folder, so a
store whose files went is refused, never started empty.
"""
from __future__ import annotations

import errno
import fcntl
import json
import os
import secrets
import signal
import socket
import stat
import subprocess
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Optional

from sg3d.core.errors import Sg3dError
from sg3d.core.stored import Row

DATABASE = "sg3d"
ROOT_USER = "root"
WRITER_GROUP = "sg3d_writer"
READER_GROUP = "sg3d_reader"
START_TIMEOUT_S = float(os.environ.get("SG3D_START_TIMEOUT", "90"))
STOP_TIMEOUT_S = 30.0


class EmbeddedStoreError(Sg3dError, RuntimeError):
    pass


class StoreStopped(EmbeddedStoreError):
    """The store was stopped with `sg3d db stop`; long-running services do not restart it."""


class StoreLost(EmbeddedStoreError):
    """The store's database or some of its files went (while the daemon ran: `LOST_FILE`; or
    found at a start by the record beside the store folder): what it held is gone, so no command
    starts it again on its own; `sg3d db start` starts an empty store."""


# The embedded store stops any single statement (sg3d's own included) after this many seconds
# (ArcadeDB's arcadedb.command.timeout); SG3D_STORE_TIMEOUT_S changes it when the store starts.
STORE_TIMEOUT_S = 30.0


def store_timeout_s() -> float:
    """The statement time limit the embedded store is started with (> 0, seconds)."""
    import math

    try:
        value = float(os.environ.get("SG3D_STORE_TIMEOUT_S", STORE_TIMEOUT_S))
    except ValueError:
        return STORE_TIMEOUT_S
    return value if math.isfinite(value) and value > 0 else STORE_TIMEOUT_S


MIN_FREE_MB = 64          # the store refuses to start with less free space on its disk
# SG3D_MIN_FREE_MB changes it (read at every check): `/health` reports a full disk below it, so an
# operator can warn earlier, and a test can see the full-disk answer without filling a disk.
MIN_FREE_ENV = "SG3D_MIN_FREE_MB"


def min_free_mb() -> float:
    """The free space (MiB) below which the store's disk counts as full (MIN_FREE_MB, or
    SG3D_MIN_FREE_MB when it is a number >= 0)."""
    import math

    try:
        value = float(os.environ.get(MIN_FREE_ENV, MIN_FREE_MB))
    except ValueError:
        return MIN_FREE_MB
    return value if math.isfinite(value) and value >= 0 else MIN_FREE_MB
STOPPED_FILE = "stopped"  # written by `sg3d db stop`, removed by the next start
# Written by the daemon when its database folder vanished under it (then it stops: a write it
# acknowledged would live only in deleted files); only `sg3d db start` removes it.
LOST_FILE = "store-lost"


def free_mb(path: Path) -> float:
    """Free space (MiB) on the disk holding `path` (or its nearest existing parent)."""
    import shutil

    path = Path(path)
    while not path.exists() and path != path.parent:
        path = path.parent
    return shutil.disk_usage(path).free / 2 ** 20


def disk_full_message(path: Path, minimum_mb: Optional[float] = None) -> Optional[str]:
    """'the disk holding PATH is full (N MB free)' when it has less than `minimum_mb` (default
    `min_free_mb()`) free, else None."""
    minimum_mb = min_free_mb() if minimum_mb is None else minimum_mb
    try:
        free = free_mb(path)
    except OSError:
        return None
    if free >= minimum_mb:
        return None
    return f"the disk holding {path} is full ({free:.0f} MB free; the store needs at least {minimum_mb:g} MB)"


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
    users: bool = False  # the daemon installed sg3d's writer and reader (older ones only had root)

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


PROC = Path("/proc")
HEAL_WAIT_S = 3.0  # the daemon rewrites a deleted server.json within a second
PRIVATE_SUBDIR = "sg3d-store"


def store_dir(requested: Path) -> Path:
    """Where the store's files go for SG3D_HOME=`requested`.

    A directory sg3d creates (or one that is already private to this user) is used as it is. An
    existing directory that others may enter (/tmp, a shared folder) is never chmod-ed: the store
    goes into a private subdirectory of it instead."""
    try:
        st = requested.stat()
    except OSError:
        return requested  # sg3d will create it, private
    if st.st_uid == os.getuid() and not st.st_mode & 0o077:
        return requested
    return requested / PRIVATE_SUBDIR


def check_private(path: Path) -> None:
    """EmbeddedStoreError unless `path` is a real directory (not a symbolic link) that this user
    owns and only it may enter. In a shared home (/tmp, mode 1777) another user may have put a
    link or a folder of theirs where the store goes: its files (a `password` there would become
    the store's root password) are never used."""
    try:
        st = os.lstat(path)
    except OSError as exc:
        raise EmbeddedStoreError(f"cannot use the store directory {path}: {exc.strerror or exc}") from None
    why = None
    if stat.S_ISLNK(st.st_mode):
        why = "it is a symbolic link"
    elif not stat.S_ISDIR(st.st_mode):
        why = "it is not a directory"
    elif st.st_uid != os.getuid():
        why = "another user owns it"
    elif st.st_mode & 0o077:
        why = f"others may enter it (mode {stat.S_IMODE(st.st_mode):o})"
    if why:
        raise EmbeddedStoreError(f"refusing the store directory {path}: {why}; the store keeps its passwords "
                                 f"only in a directory of this user that only it may enter (mode 0700; "
                                 f"remove it, or choose another --home)")


def read_secret(path: Path) -> str:
    """The text of one of the store's secret files (`password`, `users.json`), opened without
    following a symbolic link; EmbeddedStoreError unless it is a regular file this user owns that
    no one else may write (one others may only read is made 0600 through the open file)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        if exc.errno in (errno.ELOOP, errno.EMLINK):
            raise EmbeddedStoreError(f"refusing the store's secret file {path}: it is a symbolic link; "
                                     f"delete it and run `sg3d db stop`") from None
        raise
    try:
        st = os.fstat(fd)
        why = None
        if not stat.S_ISREG(st.st_mode):
            why = "it is not a regular file"
        elif st.st_uid != os.getuid():
            why = "another user owns it"
        elif st.st_mode & 0o022:
            why = f"others may write it (mode {stat.S_IMODE(st.st_mode):o})"
        if why:
            raise EmbeddedStoreError(f"refusing the store's secret file {path}: {why}; delete it and run "
                                     f"`sg3d db stop`")
        if st.st_mode & 0o077:
            os.fchmod(fd, 0o600)
        return os.read(fd, 1 << 20).decode("utf-8", "replace").strip()
    finally:
        os.close(fd)


def _cmdline(pid: int) -> list[str]:
    try:
        raw = (PROC / str(pid) / "cmdline").read_bytes()
    except OSError:
        return []
    return raw.decode(errors="replace").split("\0")[:-1]


def daemon_pids(home: Path) -> list[int]:
    """Processes running `python -m sg3d.graphdb.daemon HOME` for this home (Linux /proc; elsewhere
    empty, and the lock files alone tell). A zombie has no command line, so it never counts."""
    if not PROC.is_dir():
        return []
    me, found = os.getpid(), []
    for entry in PROC.iterdir():
        if not entry.name.isdigit() or int(entry.name) == me:
            continue
        args = _cmdline(int(entry.name))
        if len(args) >= 3 and args[-3:-1] == ["-m", "sg3d.graphdb.daemon"] and _same_home(entry, args[-1], home):
            found.append(int(entry.name))
    return found


def _same_home(proc: Path, started_with: str, home: Path) -> bool:
    """Whether a daemon started with `started_with` serves `home`: the same path, or (a daemon of
    this user's) a path that now leads to it (its home was moved and a link put in its place)."""
    if started_with == str(home):
        return True
    try:
        return proc.stat().st_uid == os.getuid() and os.path.realpath(started_with) == os.path.realpath(home)
    except OSError:
        return False


def process_alive(pid: int) -> bool:
    """True while `pid` runs. A zombie (dead, not yet reaped by its parent) counts as gone once
    all its threads have exited: only then has it released its files and locks."""
    try:
        fields = dict(line.split(":", 1) for line in (PROC / str(pid) / "status").read_text().splitlines()
                      if ":" in line)
        state, threads = fields["State"].split()[0], int(fields["Threads"])
        return not (state in ("Z", "X") and threads <= 1)
    except OSError:
        pass
    except (KeyError, ValueError, IndexError):
        return True
    try:
        os.kill(pid, 0)
        return True
    except ProcessLookupError:
        return False
    except PermissionError:
        return True


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
        self.requested = Path(home).expanduser().resolve()
        self.home = store_dir(self.requested)
        self._child: Optional[subprocess.Popen] = None

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

    def _secret_file(self, path: Path, make: Callable[[], str]) -> str:
        """A generated secret kept in a file only the user can read (created once, race-free),
        in the private store directory (`check_private`), never through a symbolic link."""
        check_private(self.home)
        try:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
        except FileExistsError:
            pass  # made before, or by another sg3d a moment ago
        else:
            with os.fdopen(fd, "w") as f:
                f.write(make())
        text = read_secret(path)
        if not text:  # the other writer has not finished yet
            time.sleep(0.05)
            text = read_secret(path)
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
            known = {"pid", "bolt_port", "http_port", "database", "started_at", "users"}
            return ServerInfo(credentials=self.credentials(), **{k: v for k, v in data.items() if k in known})
        except (OSError, ValueError, TypeError):
            return None

    # -- state ---------------------------------------------------------------------------
    def daemon_pids(self) -> list[int]:
        """The live daemons of this home, found by process identity (see `daemon_pids`)."""
        if self._child is not None:
            self._child.poll()  # reap our own child if it died: a zombie is no daemon
        return daemon_pids(self.home)

    def status(self) -> Status:
        try:
            return self._status()
        except OSError as exc:
            raise EmbeddedStoreError(f"cannot use the store directory {self.home}: {exc.strerror or exc}") from None

    def _status(self) -> Status:
        """Running = a daemon process of this home exists, or someone holds server.lock.

        The lock says it for a daemon that owns its files; the process scan also finds one whose
        server.lock or server.json was deleted (it writes them again within a second)."""
        if not self.home.is_dir():
            return Status(False)
        pids = self.daemon_pids()
        locked = False
        if self.lock_path.exists():
            with _flock(self.lock_path, blocking=False) as free:
                locked = not free
        if not locked and not pids:
            # no daemon: whatever server.json says is left from a crash
            stale = self.info_path.exists()
            if stale:
                self.info_path.unlink(missing_ok=True)
            return Status(False, recovered_stale=stale)
        info = self._read_info()
        if info is not None and PROC.is_dir() and info.pid not in pids:
            info = None  # a left-over file naming a process that is not this home's daemon
        if info is None and pids:
            info = self._wait_info(pids, HEAL_WAIT_S)
        return Status(True, info)

    def _wait_info(self, pids: list[int], seconds: float) -> Optional[ServerInfo]:
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            info = self._read_info()
            if info is not None and info.pid in pids:
                return info
            time.sleep(0.1)
        return None

    def ensure_running(self) -> ServerInfo:
        """Return the running daemon's info, starting it first if needed."""
        st = self.status()
        if st.running and st.info is not None and port_open(st.info.bolt_port):
            if not st.info.users:
                raise EmbeddedStoreError(f"the store in {self.home} was started by an older sg3d without "
                                         f"sg3d's own users; run `sg3d db stop` once and retry")
            return st.info
        return self.start()

    def ensure_home(self) -> None:
        """Create the store directory, private to this user (never chmod-ing one sg3d did not create)."""
        try:
            self.home.parent.mkdir(parents=True, exist_ok=True)
            if not os.path.islink(self.home):   # a link is refused below, never followed
                self.home.mkdir(mode=0o700, exist_ok=True)
            check_private(self.home)
        except OSError as exc:
            raise EmbeddedStoreError(f"cannot use the store directory {self.home}: {exc.strerror or exc}") from None

    def start(self) -> ServerInfo:
        try:
            return self._start()
        except OSError as exc:
            raise EmbeddedStoreError(f"cannot use the store directory {self.home}: {exc.strerror or exc}") from None

    @property
    def stopped_path(self) -> Path:
        return self.home / STOPPED_FILE

    def mark_stopped(self) -> None:
        """Record an explicit stop: services (`sg3d serve`, `sg3d mcp`) leave the store stopped."""
        if self.home.is_dir() and not self.home.is_symlink():
            self.stopped_path.touch(mode=0o600)

    def was_stopped(self) -> bool:
        return self.stopped_path.exists()

    @property
    def database_dir(self) -> Path:
        """ArcadeDB's folder of sg3d's database (`<home>/databases/databases/sg3d`)."""
        return self.home / "databases" / "databases" / DATABASE

    @property
    def lost_path(self) -> Path:
        return self.home / LOST_FILE

    @property
    def record_path(self) -> Path:
        """The record, beside the store folder, that a database was created (`filewatch.record_path`)."""
        from sg3d.graphdb.filewatch import record_path

        return record_path(self.home)

    def lost(self) -> Optional[str]:
        """Why the store's data is gone, or None: its database folder vanished while the daemon ran
        (LOST_FILE), or the record beside the store folder says a database was created and its
        folder or files are gone (the whole store folder deleted, a tmp cleaner). Cleared by
        `accept_lost` (`sg3d db start`)."""
        from sg3d.graphdb.filewatch import gone_from, read_record

        if os.path.lexists(self.lost_path):     # also False when the home is no directory
            try:
                return read_secret(self.lost_path) or "the store's database folder vanished while it ran"
            except FileNotFoundError:
                pass
            except (OSError, EmbeddedStoreError):
                return f"{self.lost_path} exists (unreadable): the store's database folder vanished while it ran"
        record = read_record(self.record_path)
        return None if record is None else gone_from(record, self.database_dir)

    def accept_lost(self) -> Optional[str]:
        """Clear the lost-store mark and the record of a database that is gone (the user starts an
        empty store); what it said, or None."""
        why = self.lost()
        if why is not None:
            self.lost_path.unlink(missing_ok=True)
            self.record_path.unlink(missing_ok=True)
        return why

    def sql(self, command: str, timeout_s: float = 600.0, limit: int = -1) -> list[Row]:
        """The result rows of one SQL `command` of sg3d's own (never user text: the store's checks)
        on the running daemon's database, at most `limit` rows (-1: all). The Bolt plugin speaks only
        Cypher, so this goes through the daemon's HTTP API (loopback, its random port) as the store's
        root user, whose password only this user can read. EmbeddedStoreError when it cannot run."""
        import base64
        import urllib.error
        import urllib.request

        st = self.status()
        if not st.running or st.info is None:
            raise EmbeddedStoreError(f"the embedded store in {self.home} is not running")
        auth = base64.b64encode(f"{ROOT_USER}:{self.password()}".encode()).decode()
        request = urllib.request.Request(
            f"http://127.0.0.1:{st.info.http_port}/api/v1/command/{DATABASE}",
            data=json.dumps({"language": "sql", "command": command, "limit": limit}).encode(),
            headers={"Authorization": f"Basic {auth}", "Content-Type": "application/json"})
        what = command.split(" FROM ")[0][:40]
        try:
            with urllib.request.urlopen(request, timeout=timeout_s) as response:   # noqa: S310 - loopback
                body = json.loads(response.read())
        except urllib.error.HTTPError as exc:
            detail = exc.read(2000).decode("utf-8", "replace")
            try:
                detail = json.loads(detail).get("detail") or json.loads(detail).get("error") or detail
            except ValueError:
                pass
            line = (str(detail).strip().splitlines() or [""])[0][:300]
            raise EmbeddedStoreError(f"the store's {what} failed (HTTP {exc.code}): {line}") from None
        except (OSError, ValueError) as exc:
            raise EmbeddedStoreError(f"the store's {what} could not run: {exc}") from None
        return [row for row in body.get("result") or [] if isinstance(row, dict)]

    def check_database(self, timeout_s: float = 600.0) -> dict:
        """ArcadeDB's own integrity check (SQL `CHECK DATABASE`: pages, records, edges, indexes)
        of the running daemon's database: its result row (see `sql`)."""
        rows = self.sql("CHECK DATABASE", timeout_s)
        return rows[0] if rows else {}

    def _start(self) -> ServerInfo:
        self.ensure_home()
        lost = self.lost()
        if lost:
            raise StoreLost(f"{lost}; what it held is gone (restore your backup into {self.home / 'databases'}, "
                            f"or `sg3d db start` to start an empty store deliberately)")
        full = disk_full_message(self.home)
        if full:
            raise EmbeddedStoreError(full)
        self.stopped_path.unlink(missing_ok=True)
        with _flock(self.home / "start.lock", blocking=True, timeout=START_TIMEOUT_S) as got:
            if not got:
                raise EmbeddedStoreError(f"another sg3d is still starting the store in {self.home}")
            st = self.status()
            if st.running:
                if st.info is not None:
                    return st.info
                if not self.daemon_pids():
                    raise EmbeddedStoreError(
                        f"{self.lock_path} is held by a process that is not this home's store daemon; "
                        f"stop it (see `fuser {self.lock_path}`) and retry")
                return self._wait_ready(None)
            self.password()
            self.credentials()
            log = open(self.log_path, "ab")
            proc = subprocess.Popen(
                [sys.executable, "-m", "sg3d.graphdb.daemon", str(self.home)],
                stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                cwd=self.home, start_new_session=True, env=dict(os.environ),
            )
            log.close()
            self._child = proc
            return self._wait_ready(proc)

    def _wait_ready(self, proc: Optional[subprocess.Popen]) -> ServerInfo:
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline:
            if proc is not None and proc.poll() is not None:
                raise EmbeddedStoreError(
                    f"the embedded store exited during start-up (code {proc.returncode}); "
                    f"last log lines:\n{self._log_tail()}")
            if proc is None and not self.daemon_pids() and PROC.is_dir():
                raise EmbeddedStoreError(f"the embedded store in {self.home} stopped during start-up; see {self.log_path}")
            info = self._read_info()
            if info is not None and port_open(info.bolt_port):
                return info
            time.sleep(0.1)
        if proc is not None:
            proc.kill()
            proc.wait()
        raise EmbeddedStoreError(
            f"the embedded store did not start within {START_TIMEOUT_S:.0f} s; see {self.log_path}")

    def stop(self) -> bool:
        """Stop the daemon; False if it was not running. Raises EmbeddedStoreError when a
        daemon runs that cannot be stopped (or the lock is held by an unknown process).

        A store folder that became a symbolic link while the daemon ran is trusted for nothing:
        the daemon is then found by process identity alone and stopped, nothing is read there."""
        if os.path.islink(self.home):
            pids = set(self.daemon_pids())
            return bool(pids) and self._signal(pids, clear=False)
        st = self.status()
        if not st.running:
            return False
        pids = set(self.daemon_pids())
        if st.info is not None:
            pids.add(st.info.pid)
        if not pids:
            raise EmbeddedStoreError(
                f"{self.lock_path} is held, but no store daemon of this home was found; "
                f"see `fuser {self.lock_path}`")
        return self._signal(pids, clear=True)

    def _signal(self, pids: set[int], clear: bool) -> bool:
        """TERM, then KILL, the daemon `pids` until they are gone (True); `clear`: then clear a
        killed daemon's leftovers."""
        for sig, wait_s in ((signal.SIGTERM, STOP_TIMEOUT_S), (signal.SIGKILL, 5.0)):
            for pid in pids:
                try:
                    os.kill(pid, sig)
                except ProcessLookupError:
                    pass
                except PermissionError:
                    raise EmbeddedStoreError(f"not allowed to stop the store daemon pid {pid}") from None
            deadline = time.monotonic() + wait_s
            while time.monotonic() < deadline:
                if not any(process_alive(pid) for pid in pids) and not self.daemon_pids():
                    if clear:
                        self.status()  # clears the leftovers of a killed daemon
                    return True
                time.sleep(0.1)
        raise EmbeddedStoreError(f"the store daemon (pid {', '.join(map(str, sorted(pids)))}) did not stop")

    def _log_tail(self, n: int = 15) -> str:
        try:
            return "\n".join(self.log_path.read_text(errors="replace").splitlines()[-n:])
        except OSError:
            return "(no log)"
