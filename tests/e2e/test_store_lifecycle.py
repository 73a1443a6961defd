"""The embedded store behaves like a local daemon: status/start/stop, stale recovery, one server."""
from __future__ import annotations

import fcntl
import json
import os
import signal
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from sg3d.graphdb.embedded import EmbeddedServer, process_alive
from tests.cli_helpers import sg3d


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
    t0 = time.monotonic()
    while process_alive(info.pid) and time.monotonic() - t0 < 20:
        time.sleep(0.05)
    assert time.monotonic() - t0 < 5  # a dead, unreaped child (zombie) counts as gone
    status = server.status()
    assert not status.running and status.recovered_stale
    assert not server.info_path.exists()
    again = server.ensure_running()
    assert again.pid != info.pid


def test_a_deleted_lock_or_info_file_neither_hides_the_daemon_nor_hangs(home):
    server = EmbeddedServer(home)
    info = server.start()
    server.lock_path.unlink()
    status = server.status()
    assert status.running and status.info.pid == info.pid
    out = sg3d(home, "cypher", "RETURN 1 AS one", "--json", timeout=60)
    assert out.returncode == 0, out.stderr
    assert server.daemon_pids() == [info.pid]            # no second daemon
    server.info_path.unlink()
    t0 = time.monotonic()
    out = sg3d(home, "cypher", "RETURN 2 AS two", "--json", timeout=60)
    assert out.returncode == 0, out.stderr
    assert time.monotonic() - t0 < 30                     # was a 90 s wait
    assert server.daemon_pids() == [info.pid]
    deadline = time.monotonic() + 5
    while not (server.lock_path.exists() and server.info_path.exists()) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert server.lock_path.exists() and server.info_path.exists()  # the daemon restored them
    server.info_path.unlink()
    out = sg3d(home, "db", "stop", timeout=60)
    assert out.returncode == 0 and "stopped" in out.stdout, out.stderr
    assert not process_alive(info.pid) and server.daemon_pids() == []


def test_db_stop_says_when_it_cannot_stop(home):
    home.mkdir(mode=0o700)
    server = EmbeddedServer(home)
    fd = os.open(server.lock_path, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(fd, fcntl.LOCK_EX)  # held by a process that is not a store daemon
    try:
        out = sg3d(home, "db", "stop", timeout=60)
        assert out.returncode == 2
        lines = out.stderr.strip().splitlines()
        assert len(lines) == 1 and "no store daemon" in lines[0], out.stderr
        out = sg3d(home, "cypher", "RETURN 1", timeout=60)
        assert out.returncode == 2 and "not this home's store daemon" in out.stderr, out.stderr
    finally:
        os.close(fd)


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
