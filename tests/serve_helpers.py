"""A real `sg3d serve` application on a free loopback port (uvicorn in a thread)."""
from __future__ import annotations

import socket
import threading
import time
from contextlib import contextmanager

from sg3d.testing import kitchen_body  # noqa: F401 - the tests take the body from here


@contextmanager
def running_server(settings, token: str, **app_options):
    """Serve `create_app(settings, token, **app_options)` with uvicorn on a free loopback port;
    yields the base URL."""
    from sg3d.server.http import create_app

    api = create_app(settings, token, **app_options)
    try:
        with serving(api) as url:
            yield url
    finally:
        api.state.stores.close()


@contextmanager
def serving(api):
    """Serve the ASGI application `api` with uvicorn on a free loopback port; yields the base URL."""
    import uvicorn

    from sg3d.graphdb.embedded import free_port

    port = free_port()
    server = uvicorn.Server(uvicorn.Config(api, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if not thread.is_alive() or time.monotonic() > deadline:
            raise RuntimeError("uvicorn did not start")
        time.sleep(0.02)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(10)


@contextmanager
def serve_process(home, *options: str, start_s: float = 120):
    """The console command `sg3d --home HOME serve --port P *options` in a process of its own,
    once /health answers 200; yields the base URL, and ends it with SIGTERM."""
    import os
    import signal
    import subprocess
    import sys

    import httpx

    from sg3d.graphdb.embedded import free_port

    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    port = free_port()
    env = {**{k: v for k, v in os.environ.items() if k != "SG3D_URI"},
           "PYTHONPATH": repo + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(home), "serve", "--port", str(port), *options],
                            env=env, start_new_session=True)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + start_s
        while True:
            try:
                if httpx.get(base + "/health", timeout=10).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            assert proc.poll() is None and time.monotonic() < deadline, "sg3d serve did not start"
            time.sleep(0.2)
        yield base
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(30)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()


def reply_status(sock: socket.socket) -> int:
    """The status of the reply that comes on `sock` (0 when none came before it closed)."""
    reply = b""
    try:
        while b"\r\n" not in reply:
            more = sock.recv(4096)
            if not more:
                break
            reply += more
    except (ConnectionResetError, socket.timeout):
        pass
    return int(reply.split()[1]) if reply.startswith(b"HTTP/") else 0
