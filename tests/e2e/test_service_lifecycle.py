"""The service and the store's lifecycle: an explicit stop stays stopped, a restart is a 503 with
Retry-After, a full disk is named (a real daemon, a real server, a real client)."""
from __future__ import annotations

import time

import httpx
import pytest
from click.testing import CliRunner

from tests.serve_helpers import kitchen_body, running_server


def test_an_explicit_stop_stays_stopped_until_db_start(tmp_path):
    from sg3d.cli import cli
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings

    home = tmp_path / "home"
    daemon = EmbeddedServer(home)
    daemon.ensure_running()
    runner = CliRunner()
    try:
        token = ensure_token(home)
        with running_server(Settings(home=home), token) as url:
            c = httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120)
            assert c.post("/ingest", json=kitchen_body()).status_code == 200
            assert runner.invoke(cli, ["--home", str(home), "db", "stop"]).output.strip() == "stopped"
            for _ in range(3):
                health = httpx.get(url + "/health")
                assert health.status_code == 503 and "was stopped" in health.json()["status"]
                r = c.get("/rooms")
                assert r.status_code == 503 and r.json()["detail"] == "the store was stopped; `sg3d db start`"
            assert not daemon.status().running, "a request restarted the store"
            assert runner.invoke(cli, ["--home", str(home), "db", "start"]).exit_code == 0
            r = c.get("/rooms")
            assert r.status_code == 200 and r.json()[0]["objects"] == 10
    finally:
        daemon.stop()


def test_store_failures_map_to_503_with_retry_after_never_500():
    from neo4j.exceptions import AuthError, ServiceUnavailable, SessionExpired

    from sg3d.server.http import store_failure
    from sg3d.settings import Settings

    settings = Settings(uri="bolt://127.0.0.1:1")
    for exc in (ServiceUnavailable("gone"), SessionExpired("gone"), AuthError("restarting")):
        status, detail, headers = store_failure(exc, settings)
        assert status == 503 and headers.get("Retry-After"), (exc, status)
    assert store_failure(KeyError("x"), settings)[0] == 500


def test_a_full_disk_is_named_and_start_fails_fast(tmp_path, monkeypatch):
    from sg3d.graphdb import embedded

    monkeypatch.setattr(embedded, "MIN_FREE_MB", 10 ** 12)     # more than any disk has: it reads as full
    t0 = time.monotonic()
    with pytest.raises(embedded.EmbeddedStoreError, match="is full .* MB free"):
        embedded.EmbeddedServer(tmp_path / "home").start()
    assert time.monotonic() - t0 < 5
    assert str(tmp_path / "home") in embedded.disk_full_message(tmp_path / "home")


def test_serve_on_an_unusable_home_is_one_line_exit_2(tmp_path):
    """A home that cannot hold the store (here: below a file, which even root cannot write into)."""
    import subprocess
    import sys

    from sg3d.graphdb.embedded import free_port

    blocker = tmp_path / "file"
    blocker.write_text("x")
    env = {k: v for k, v in __import__("os").environ.items() if k != "SG3D_URI"}
    out = subprocess.run([sys.executable, "-m", "sg3d", "--home", str(blocker / "home"), "serve",
                          "--port", str(free_port())], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 2, out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "cannot use the store directory" in lines[0] and "Traceback" not in out.stderr
