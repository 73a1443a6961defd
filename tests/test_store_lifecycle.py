"""The embedded store behaves like a local daemon: status/start/stop, stale recovery, one server."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from graphdb.embedded import EmbeddedServer


def sg3d(home, *args, timeout=120):
    env = dict(os.environ, SG3D_HOME=str(home))
    env.pop("SG3D_URI", None)
    return subprocess.run([sys.executable, "-m", "sg3d", *args], capture_output=True, text=True,
                          env=env, timeout=timeout)


@pytest.fixture
def home(tmp_path):
    home = tmp_path / "home"
    yield home
    EmbeddedServer(home).stop()


def test_db_status_start_again_stop(home):
    out = sg3d(home, "db", "status")
    assert out.returncode == 0 and "not running" in out.stdout
    out = sg3d(home, "db", "start")
    assert out.returncode == 0 and out.stdout.startswith("started"), out.stderr
    out = sg3d(home, "db", "start")
    assert out.returncode == 0 and "already running" in out.stdout
    status = json.loads(sg3d(home, "db", "status", "--json").stdout)
    assert status["running"] and status["uri"].startswith("bolt://127.0.0.1:")
    assert oct((home / "password").stat().st_mode & 0o777) == "0o600"
    out = sg3d(home, "db", "stop")
    assert out.returncode == 0 and "stopped" in out.stdout
    assert "not running" in sg3d(home, "db", "status").stdout


def test_a_command_starts_the_store_on_demand_and_the_next_reuses_it(home):
    out = sg3d(home, "cypher", "RETURN 1 AS one", "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == [{"one": 1}]
    pid = EmbeddedServer(home).status().info.pid
    assert sg3d(home, "cypher", "RETURN 2 AS two").returncode == 0
    assert EmbeddedServer(home).status().info.pid == pid


def test_two_starts_at_once_make_one_server(home):
    servers = [EmbeddedServer(home), EmbeddedServer(home)]
    with ThreadPoolExecutor(2) as pool:
        infos = list(pool.map(lambda s: s.ensure_running(), servers))
    assert infos[0].pid == infos[1].pid
    assert infos[0].bolt_port == infos[1].bolt_port


def test_a_crashed_daemon_is_detected_and_recovered(home):
    server = EmbeddedServer(home)
    info = server.start()
    os.kill(info.pid, signal.SIGKILL)
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        try:
            os.kill(info.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    time.sleep(0.3)
    status = server.status()
    assert not status.running and status.recovered_stale
    assert not server.info_path.exists()
    again = server.ensure_running()
    assert again.pid != info.pid


def test_refused_uri_gives_one_clear_line(home):
    out = sg3d(home, "--uri", "bolt://127.0.0.1:9", "cypher", "RETURN 1", timeout=60)
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: cannot reach the graph store")
    assert "Traceback" not in out.stderr


def test_cypher_error_prints_the_servers_message(home):
    out = sg3d(home, "cypher", "MATCH (n RETURN n")
    assert out.returncode == 2
    assert out.stderr.startswith("error: Neo.ClientError.Statement.SyntaxError")
    assert "Traceback" not in out.stderr
