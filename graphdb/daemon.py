"""Process entry of the embedded store: `python -m graphdb.daemon HOME`.

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

from graphdb.embedded import DATABASE, READER_GROUP, WRITER_GROUP, Credentials, EmbeddedServer, free_port

# sg3d never reads files or URLs through LOAD CSV: the engine is told so, whoever logs in
CLOSED_SETTINGS = {
    "arcadedb.opencypher.loadCsv.allowFileUrls": False,
    "arcadedb.opencypher.loadCsv.allowRemoteUrls": False,
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
    import jpype

    config = jpype.JClass("com.arcadedb.GlobalConfiguration")
    for key, value in CLOSED_SETTINGS.items():
        setting = config.findByKey(key)
        if setting is not None:
            setting.setValue(value)


def install_users(server, creds: Credentials) -> None:
    """(Re)create sg3d's groups and users from the credentials file, at every start: a lost or
    regenerated users.json is recovered by restarting the store."""
    import jpype

    JSONObject = jpype.JClass("com.arcadedb.serializer.json.JSONObject")
    security = server._java_server.getSecurity()
    for group, spec in GROUPS.items():
        security.saveGroup(DATABASE, group, JSONObject(json.dumps(spec)))
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


def main(home: str) -> None:
    server_home = EmbeddedServer(home)
    lock_fd = _take_lock(server_home.lock_path)
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
            "http_port": http_port,
            "server_plugins": "Bolt:com.arcadedb.bolt.BoltProtocolPlugin",
            "bolt_port": bolt_port,
        },
    )
    server.start()
    if not (server_home.home / "databases" / DATABASE).exists():
        server.create_database(DATABASE)
    install_users(server, server_home.credentials())

    stop = threading.Event()
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, lambda *_: stop.set())

    tmp = server_home.info_path.with_suffix(".tmp")
    tmp.write_text(json.dumps({
        "pid": os.getpid(), "bolt_port": bolt_port, "http_port": http_port,
        "database": DATABASE, "started_at": time.time(),
    }))
    os.replace(tmp, server_home.info_path)
    print(f"sg3d embedded store ready: bolt://127.0.0.1:{bolt_port} database {DATABASE}", flush=True)

    stop.wait()
    print("stopping", flush=True)
    server_home.info_path.unlink(missing_ok=True)
    try:
        server.stop()
    finally:
        os.close(lock_fd)  # releases the lock: status now reads "not running"
    # JPype's JVM shutdown can linger; the data is flushed by server.stop()
    os._exit(0)


if __name__ == "__main__":
    main(sys.argv[1])
