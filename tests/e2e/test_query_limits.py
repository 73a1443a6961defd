"""Limits on a user's own Cypher that the store enforces: statement length, a linear scan of
comments and strings, a time limit that stops the statement in the daemon (a real embedded
store started with a short limit), and no sleeping."""
from __future__ import annotations

import os
import threading
import time

import pytest

HEAVY = "UNWIND range(1, 30000) AS a UNWIND range(1, 30000) AS b RETURN count(*) AS n"
LIMIT_S = 3.0


@pytest.fixture(scope="module")
def limited_store(tmp_path_factory):
    """An embedded store of its own whose statements stop after LIMIT_S seconds."""
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.store import Store

    home = tmp_path_factory.mktemp("limited-home")
    old = os.environ.get("SG3D_STORE_TIMEOUT_S")
    os.environ["SG3D_STORE_TIMEOUT_S"] = str(LIMIT_S)
    try:
        server = EmbeddedServer(home)
        info = server.ensure_running()
    finally:
        if old is None:
            os.environ.pop("SG3D_STORE_TIMEOUT_S")
        else:
            os.environ["SG3D_STORE_TIMEOUT_S"] = old
    writer = Store(info.uri, info.writer_auth, info.database)
    writer.ensure_schema()
    reader = Store(info.uri, info.reader_auth, info.database, read_only=True, writes_via=lambda: writer)
    yield server, info, reader
    reader.close()
    writer.close()
    server.stop()


def _cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process and its threads (s)."""
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_a_96_kb_comment_statement_is_handled_in_under_a_second(store):
    from sg3d.app.errors import AppError
    from sg3d.app.graph import check_statement, read_only_cypher, write_words

    evil = "/*x" * 32_000
    t0 = time.monotonic()
    write_words(evil)
    with pytest.raises(AppError, match="longer than"):
        read_only_cypher(store, "MATCH (n) RETURN n " + evil)
    assert time.monotonic() - t0 < 1.0
    t0 = time.monotonic()
    check_statement("MATCH (n) RETURN n " + "/*x" * 6000)       # below the length limit: linear scan
    write_words("'x" * 6000 + '"y' * 3000 + "`z" * 3000)
    assert time.monotonic() - t0 < 1.0


def test_a_heavy_query_stops_at_the_store_limit(limited_store):
    from sg3d.app.errors import AppError
    from sg3d.app.graph import read_only_cypher

    _, _, reader = limited_store
    t0 = time.monotonic()
    with pytest.raises(AppError, match="TimedOut|timeout"):
        read_only_cypher(reader, HEAVY)
    assert time.monotonic() - t0 < LIMIT_S + 3


def test_an_abandoned_query_stops_and_frees_the_daemon(limited_store):
    from sg3d.app.graph import run_rolled_back
    from sg3d.graphdb.store import Store

    server, info, reader = limited_store
    pid = info.pid
    quitter = Store(info.uri, info.reader_auth, info.database, read_only=True)

    def run():
        try:
            run_rolled_back(quitter, HEAVY, {})
        except Exception:  # noqa: BLE001 - the client gave up; whatever the driver raises is expected
            pass

    threading.Thread(target=run, daemon=True).start()
    time.sleep(0.5)
    quitter.close()                               # the caller gives up
    time.sleep(LIMIT_S + 1.0)
    before, t0 = _cpu_seconds(pid), time.monotonic()
    time.sleep(2.0)
    busy = (_cpu_seconds(pid) - before) / (time.monotonic() - t0)
    assert busy < 0.35, f"the daemon still uses {busy:.2f} cores after the limit"
    t0 = time.monotonic()
    reader.read("plan_rooms")
    assert time.monotonic() - t0 < 1.0


@pytest.mark.parametrize("statement", ["RETURN util.sleep(15000)", "RETURN Sleep (1)",
                                       "MATCH (n) /* c */ RETURN apoc.util.sleep(10)"])
def test_sleeping_is_refused(store, statement):
    from sg3d.app.errors import Refused
    from sg3d.app.graph import read_only_cypher

    with pytest.raises(Refused, match="sleep"):
        read_only_cypher(store, statement)


def test_sleep_in_a_string_or_a_name_is_fine(store):
    from sg3d.app.graph import read_only_cypher

    out = read_only_cypher(store, "RETURN 'sleep(1)' AS s, 1 AS sleepy")
    assert out["rows"] == [{"s": "sleep(1)", "sleepy": 1}]


def test_cli_cypher_refuses_a_long_statement_in_one_line(embedded_home, store):
    from click.testing import CliRunner

    from sg3d.cli import cli

    r = CliRunner().invoke(cli, ["--home", str(embedded_home), "cypher", "RETURN 1 " + "/*x" * 10_000])
    assert r.exit_code == 2 and "longer than" in r.output and len(r.output) < 300
