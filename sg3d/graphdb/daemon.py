"""Process entry of the embedded store: `python -m sg3d.graphdb.daemon HOME`.

Started detached by `EmbeddedServer.start`; runs ArcadeDB (its own bundled JRE) with the Bolt
plugin on loopback until SIGTERM/SIGINT, then stops it cleanly.
"""
from __future__ import annotations

import fcntl
import json
import os
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any, Optional

from sg3d.graphdb.filewatch import FileWatch
from sg3d.graphdb.watchdog import Watchdog
from sg3d.graphdb.embedded import (
    DATABASE,
    READER_GROUP,
    WRITER_GROUP,
    Credentials,
    EmbeddedServer,
    daemon_pids,
    free_port,
    store_timeout_s,
)

# How often the daemon looks at its database files (a look costs ~1 ms): writes acknowledged in
# the moment between a file's deletion and the next look are lost with it.
WATCH_S = 0.1

# sg3d never reads files or URLs through LOAD CSV: the engine is told so, whoever logs in
CLOSED_SETTINGS = {
    "arcadedb.opencypher.loadCsv.allowFileUrls": False,
    "arcadedb.opencypher.loadCsv.allowRemoteUrls": False,
    "arcadedb.command.timeout": 3000,
}

# ArcadeDB's per-database groups (server-groups.json). The reader may read records and nothing
# else: no create/update/delete, no schema change, no security change (which LOAD CSV of a file
# also needs). The writer may change records and the schema, but not security.
GROUPS = {
    READER_GROUP: {"resultSetLimit": -1, "readTimeout": -1, "access": [],
                   "types": {"*": {"access": ["readRecord"]}}},
    WRITER_GROUP: {"resultSetLimit": -1, "readTimeout": -1, "access": ["updateSchema"],
                   "types": {"*": {"access": ["createRecord", "readRecord", "updateRecord", "deleteRecord"]}}},
}


def close_engine_settings() -> None:
    """The engine settings above, and the time limit of every statement (a query an agent
    abandoned stops there instead of keeping a core busy until `sg3d db stop`)."""
    import jpype

    config = jpype.JClass("com.arcadedb.GlobalConfiguration")
    settings = {**CLOSED_SETTINGS, "arcadedb.command.timeout": int(store_timeout_s() * 1000)}
    for key, value in settings.items():
        setting = config.findByKey(key)
        if setting is not None:
            setting.setValue(value)


def install_users(server: Any, creds: Credentials) -> None:
    """(Re)create sg3d's groups and users from the credentials file, at every start: a lost or
    regenerated users.json is recovered by restarting the store."""
    import jpype

    JSONObject = jpype.JClass("com.arcadedb.serializer.json.JSONObject")
    security = server._java_server.getSecurity()
    for group, spec in GROUPS.items():
        security.saveGroup(DATABASE, group, JSONObject(json.dumps(spec)))
    current = {creds.writer, creds.reader}
    for user in list(security.getUsers()):
        name = str(user.getName() if hasattr(user, "getName") else user)
        if name.startswith(("sg3d_writer_", "sg3d_reader_")) and name not in current:
            security.dropUser(name)  # left by a users.json that was deleted or replaced
    for name, password, group in ((creds.writer, creds.writer_password, WRITER_GROUP),
                                  (creds.reader, creds.reader_password, READER_GROUP)):
        if security.existsUser(name):
            security.dropUser(name)
        security.createUser(JSONObject(json.dumps({
            "name": name, "password": str(security.encodePassword(password)),
            "databases": {DATABASE: [group]}})))


def _take_lock(path: Path, timeout: float = 10.0) -> int:
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    deadline = time.monotonic() + timeout
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return fd
        except BlockingIOError:
            # a `status` call may hold it for a moment; a live daemon holds it for good
            if time.monotonic() > deadline:
                print("another embedded store is running in this home", flush=True)
                sys.exit(3)
            time.sleep(0.05)


class Keeper:
    """Keeps the daemon's lifecycle files true while it runs: server.lock held by this process
    and server.json present. Someone deleting either (a cleanup script, a user) would otherwise
    make the next sg3d start a second daemon or wait for a file that never comes."""

    def __init__(self, home: EmbeddedServer, lock_fd: int):
        self.home, self.lock_fd, self.info_text = home, lock_fd, ""
        self.watch: Optional[FileWatch] = None   # the database's files, once the store opened it
    def mark_lost(self, why: str) -> None:
        """Leave `why` in the home's LOST_FILE (0600) and in the record beside the store folder: no
        command starts the store on its own again."""
        if self.watch is not None:
            self.watch.mark_lost(why)
        try:
            fd = os.open(self.home.lost_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o600)
            with os.fdopen(fd, "w") as f:
                f.write(why)
        except OSError as exc:
            print(f"cannot write {self.home.lost_path}: {exc}", flush=True)

    def write_info(self, text: str) -> None:
        self.info_text = text
        tmp = self.home.info_path.with_suffix(".tmp")
        tmp.write_text(text)
        os.replace(tmp, self.home.info_path)

    def heal(self) -> None:
        try:
            held = os.fstat(self.lock_fd).st_ino
            if not self.home.lock_path.exists() or self.home.lock_path.stat().st_ino != held:
                fd = os.open(self.home.lock_path, os.O_RDWR | os.O_CREAT, 0o600)
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except BlockingIOError:
                    os.close(fd)  # a status call holds it this instant: next round
                else:
                    os.close(self.lock_fd)
                    self.lock_fd = fd
            if self.info_text and not self.home.info_path.exists():
                self.write_info(self.info_text)
        except OSError as exc:
            print(f"cannot restore the lifecycle files: {exc}", flush=True)


def main(home: str) -> None:
    server_home = EmbeddedServer(home)
    if any(pid != os.getpid() for pid in daemon_pids(server_home.home)):
        print("another embedded store is running in this home", flush=True)
        sys.exit(3)
    lock_fd = _take_lock(server_home.lock_path)
    lost = server_home.lost()
    if lost:        # never an empty store where one existed: only `sg3d db start` clears this
        print(lost, flush=True)
        sys.exit(5)
    os.chdir(server_home.home)  # ArcadeDB writes ./log relative to the working directory

    import arcadedb_embedded as arcadedb
    from arcadedb_embedded.jvm import start_jvm

    start_jvm()
    close_engine_settings()
    bolt_port = int(os.environ.get("SG3D_BOLT_PORT") or free_port())
    http_port = int(os.environ.get("SG3D_HTTP_PORT") or free_port())
    server = arcadedb.create_server(
        root_path=str(server_home.home / "databases"),
        root_password=server_home.password(),
        config={
            # ArcadeDB always runs its HTTP API (26.10 has no setting that turns it off; sg3d's
            # `db check` uses it for CHECK DATABASE, which Bolt cannot send): it listens on loopback
            # only (the wrapper's default host) on a random port, behind the root password. The wheel
            # ships no Studio (GET / is 404) and its MCP endpoint stays off (config/mcp-config.json).
            # Production mode was tried and rejected: it replaces every error message the store
            # sends over Bolt by "The request failed", which users and agents need to read.
            "http_port": http_port,
            "server_plugins": "Bolt:com.arcadedb.bolt.BoltProtocolPlugin",
            "bolt_port": bolt_port,
        },
    )
    server.start()
    if not server_home.database_dir.exists():
        server.create_database(DATABASE)
    install_users(server, server_home.credentials())
    # ArcadeDB's own limit acts between rows only: the watchdog stops a statement whatever it computes
    Watchdog(server._java_server, store_timeout_s(), log=lambda line: print(line, flush=True)).start()

    stop = threading.Event()
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, lambda *_: stop.set())

    keeper = Keeper(server_home, lock_fd)
    keeper.watch = FileWatch(server_home.database_dir, server_home.record_path)
    if keeper.watch.problem:
        print(f"{keeper.watch.problem}: a store whose files go is not recognised at its next start", flush=True)
    keeper.write_info(json.dumps({
        "pid": os.getpid(), "bolt_port": bolt_port, "http_port": http_port,
        "database": DATABASE, "started_at": time.time(), "users": True,
    }))
    print(f"sg3d embedded store ready: bolt://127.0.0.1:{bolt_port} database {DATABASE}", flush=True)

    ticks = 0
    while not stop.wait(WATCH_S):
        ticks += 1
        if ticks % 5 == 0:
            keeper.heal()
        lost = keeper.watch.lost()
        if lost:
            keeper.mark_lost(lost)
            print(lost, flush=True)
            server_home.info_path.unlink(missing_ok=True)
            os._exit(4)     # no flush: the files it would write to are gone; every connection drops now
    print("stopping", flush=True)
    server_home.info_path.unlink(missing_ok=True)
    try:
        server.stop()
    finally:
        os.close(keeper.lock_fd)  # releases the lock: status now reads "not running"
    # JPype's JVM shutdown can linger; the data is flushed by server.stop()
    os._exit(0)


if __name__ == "__main__":
    try:
        main(sys.argv[1])
    except SystemExit as exc:
        sys.stdout.flush()
        os._exit(exc.code if isinstance(exc.code, int) else 1)
    except BaseException:  # noqa: BLE001 - the JVM's threads would keep a failed daemon alive
        import traceback

        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)
