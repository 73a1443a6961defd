"""`sg3d serve --workers N`: N worker processes through uvicorn's own process model
(`uvicorn.supervisors.Multiprocess`, what `uvicorn --workers` runs), all sharing the one store.

The parent binds the socket, starts (or finds) the store, makes a temporary folder for the
Prometheus figures of every worker (`sg3d.server.metrics`), and hands each worker its settings
through the environment (`SERVE_ENV`, JSON): uvicorn spawns fresh interpreters, which build the
app with `app()` (a factory, `factory=True`). So every worker has the same token (read from the
same file), limits, deadlines and store watch (each restarts a dead embedded store, which starts
it once however many ask) as a single-process server. The parent serves no request; it restarts a
worker that dies and stops them all on SIGTERM/SIGINT. (The environment carries a --uri store's
password too, as SG3D_PASSWORD would: a process's environment is readable by its own user only.)
"""
from __future__ import annotations

import dataclasses
import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sg3d.settings import Settings

SERVE_ENV = "SG3D_SERVE_WORKER"
FACTORY = "sg3d.server.workers:app"


def app():
    """The application of one worker process, from the settings in `SERVE_ENV`."""
    from sg3d.server.auth import ensure_token
    from sg3d.server.http import create_app
    from sg3d.settings import Settings

    given = json.loads(os.environ[SERVE_ENV])
    fields = given["settings"]
    settings = Settings(**{**fields, "home": Path(fields["home"]) if fields.get("home") else None})
    token = ensure_token(settings.embedded_home())
    return create_app(settings, token, max_body=given["max_body"], max_threads=given["threads"])


def serve_workers(settings: Settings, sock, workers: int, max_body: int, threads: int, access_log: bool) -> None:
    """Serve on the bound socket `sock` with `workers` processes until SIGTERM/SIGINT."""
    import uvicorn
    from uvicorn.supervisors import Multiprocess

    from sg3d.app.stores import StoreHandle
    from sg3d.server.metrics import MULTIPROC_ENV

    handle = StoreHandle(settings)
    handle.get()                        # start or find the store now, once, not in every worker
    handle.close()
    fields = {f.name: getattr(settings, f.name) for f in dataclasses.fields(settings)}
    fields["home"] = str(fields["home"]) if fields.get("home") else None
    figures = tempfile.mkdtemp(prefix="sg3d-metrics-")
    os.environ[MULTIPROC_ENV] = figures          # before a worker imports prometheus_client
    os.environ[SERVE_ENV] = json.dumps({"settings": fields, "max_body": max_body, "threads": threads})
    try:
        host, port = sock.getsockname()[:2]
        # a stuck store call ends at its own deadline; SIGTERM waits at most 5 s for requests in flight
        config = uvicorn.Config(FACTORY, factory=True, host=host, port=port, workers=workers, log_level="warning",
                                access_log=access_log, timeout_graceful_shutdown=5)
        Multiprocess(config, sockets=[sock]).run()
    finally:
        os.environ.pop(SERVE_ENV, None)
        shutil.rmtree(figures, ignore_errors=True)
