"""The store's own files and indexes, on private real stores (no mocks):

- the daemon watches its database files: the store folder deleted, or files deleted inside the
  database folder (what a tmp cleaner does), stop it at once; a store whose files went (while it ran,
  or while it was stopped or killed) is never started again as an empty one: every command says
  why, exit 2, until `sg3d db start` starts an empty store deliberately;

- `sg3d db check` compares every unique index with the records (a zeroed page of the Object id
  index, a duplicate id) and fails (exit 1) on NaN values and tallies that disagree with the objects.
"""
from __future__ import annotations

import json
import os
import signal
import shutil
import time

import pytest

from tests.cli_helpers import one_error_line, sg3d




# -- db check: unique indexes against the records --------------------------------------------------
def _object_id_index(server):
    """The file of the Object id unique index (ArcadeDB: `<Type>_<bucket>_<n>.<file id>.<page>.v1.umtidx`,
    one per bucket; the non-unique indexes end .numtidx)."""
    files = sorted(server.database_dir.glob("Object_0_*.umtidx"))
    assert len(files) == 1, files
    return files[0]


def test_db_check_finds_a_zeroed_page_of_the_object_id_index(own_store):
    home, server = own_store
    assert sg3d(home, "db", "check").returncode == 0
    index = _object_id_index(server)
    page = int(index.name.split(".")[2])
    server.stop()
    with open(index, "r+b") as f:
        f.write(b"\0" * page)
    out = sg3d(home, "db", "check", "--json")
    assert out.returncode == 1, out.stdout + out.stderr
    report = json.loads(out.stdout)
    assert report["integrity"] == "damaged" and any("Object[id]" in line for line in report["damage"]), report


def test_db_check_finds_a_duplicate_id_the_index_lets_through(own_store):
    """Records whose unique key repeats (what a damaged index accepts) fail `db check`, named."""
    home, server = own_store
    index = _object_id_index(server)
    page = int(index.name.split(".")[2])
    server.stop()
    with open(index, "r+b") as f:
        f.write(b"\0" * page)
    out = sg3d(home, "cypher", "--write", "MATCH (o:Object) WITH o ORDER BY o.id LIMIT 1 "
               "CREATE (:Object {id: o.id, room: o.room, label: o.label}) RETURN o.id AS id", "--json")
    assert out.returncode == 0, out.stderr      # the damaged store accepts it
    duplicate = json.loads(out.stdout)[0]["id"]
    out = sg3d(home, "db", "check", "--json")
    assert out.returncode == 1
    assert any(duplicate in line and "Object" in line for line in json.loads(out.stdout)["damage"]), out.stdout


# -- db check: values no reader can use and wrong tallies fail it -----------------------------------
def test_db_check_exits_1_on_a_nan_value_and_on_a_wrong_tally_until_repaired(own_store):
    from sg3d.settings import Settings

    home, _ = own_store
    store = Settings(home=home).store()
    try:
        store.run_raw("MATCH (o:Object) WITH o ORDER BY o.id LIMIT 1 SET o.x = $nan", {"nan": float("nan")},
                      write=True)
        out = sg3d(home, "db", "check", "--json")
        assert out.returncode == 1, out.stdout + out.stderr
        assert len(json.loads(out.stdout)["objects"]) == 1
        assert sg3d(home, "db", "check", "--repair").returncode == 0
        assert sg3d(home, "db", "check").returncode == 0
        store.run_raw("MATCH (t:Tally) SET t.n = t.n + 1", {}, write=True)
        out = sg3d(home, "db", "check")
        assert out.returncode == 1 and "tally" in out.stdout, out.stdout + out.stderr
        assert sg3d(home, "db", "check", "--repair").returncode == 0
        assert sg3d(home, "db", "check").returncode == 0
    finally:
        store.close()


# -- the daemon's files ---------------------------------------------------------------------------
def _gone_within(server, pid: int, seconds: float) -> bool:
    from sg3d.graphdb.embedded import process_alive

    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if not process_alive(pid):
            return True
        time.sleep(0.05)
    return False


def _refused_then_started_empty(home) -> None:
    """Every command that needs the store refuses (one line, why and the way out) until `db start`."""
    line = one_error_line(sg3d(home, "rooms"))
    assert "gone" in line and "sg3d db start" in line, line
    line = one_error_line(sg3d(home, "cypher", "--write", "CREATE (p:Probe {n: 1}) RETURN p.n"))
    assert "gone" in line
    out = sg3d(home, "db", "check")
    assert out.returncode == 1 and "gone" in out.stdout, out.stdout + out.stderr
    out = sg3d(home, "db", "start")
    assert out.returncode == 0 and "starting an empty store" in out.stderr, out.stdout + out.stderr
    out = sg3d(home, "rooms", "--json")
    assert out.returncode == 0 and json.loads(out.stdout) == [], out.stdout + out.stderr


def test_the_store_folder_deleted_under_the_daemon_is_never_started_empty(own_store):
    home, server = own_store
    pid = server.status().info.pid
    for _ in range(40):       # the daemon may write a file while the folder is being removed: again
        shutil.rmtree(server.home, ignore_errors=True)
        if not server.home.exists():
            break
        time.sleep(0.05)
    assert not server.home.exists()
    assert _gone_within(server, pid, 2.0), "the daemon went on with its store folder gone"
    _refused_then_started_empty(home)


def test_files_deleted_inside_the_database_folder_stop_the_daemon(own_store):
    home, server = own_store
    pid = server.status().info.pid
    for path in server.database_dir.glob("Object_0*.bucket"):     # what an age-based tmp cleaner does
        path.unlink()
    assert _gone_within(server, pid, 2.0), "the daemon went on with its files deleted"
    _refused_then_started_empty(home)


def test_files_deleted_while_the_store_was_killed_are_found_at_the_next_start(own_store):
    home, server = own_store
    pid = server.status().info.pid
    os.kill(pid, signal.SIGKILL)
    assert _gone_within(server, pid, 5.0)
    for path in server.database_dir.glob("*.bucket"):
        path.unlink()
    (server.database_dir / "schema.json").unlink()
    _refused_then_started_empty(home)


# -- a store folder swapped for a symbolic link while the daemon runs -------------------------------
def _swap_for_link(folder) -> None:
    moved = folder.with_name(folder.name + "-moved")
    folder.rename(moved)
    folder.symlink_to(moved)


@pytest.mark.parametrize("shared", [True, False], ids=["store-in-a-shared-home", "home-is-the-store"])
def test_db_stop_stops_a_daemon_whose_store_folder_became_a_link(tmp_path, shared):
    from sg3d.graphdb.embedded import EmbeddedServer, process_alive

    home = tmp_path / "home"
    home.mkdir(mode=0o777 if shared else 0o700)
    home.chmod(0o777 if shared else 0o700)
    server = EmbeddedServer(home)
    pid = server.ensure_running().pid
    try:
        _swap_for_link(server.home)
        out = sg3d(home, "db", "stop")
        assert out.returncode == 0 and "stopped" in out.stdout, out.stdout + out.stderr
        assert not process_alive(pid)
        if shared:   # the link itself is trusted for nothing else
            line = one_error_line(sg3d(home, "rooms"))
            assert "symbolic link" in line, line
    finally:
        if process_alive(pid):
            os.kill(pid, signal.SIGKILL)


# -- a statement that computes inside one row ------------------------------------------------------
RUNAWAY = ("WITH range(1, 2000) AS r RETURN reduce(s = 0, a IN r | s + reduce(t = 0, b IN r | "
           "t + reduce(u = 0, c IN r | u + c))) AS x")


def _cpu_seconds(pid: int) -> float:
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_a_statement_computing_inside_one_row_is_stopped_by_the_limit(tmp_path):
    """The store's limit (2 s here) stops a statement whatever it computes inside a row: the caller
    gets the reason within the limit + 2 s, and the daemon's cores go idle."""
    import threading

    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.settings import Settings

    home = tmp_path / "home"
    server = EmbeddedServer(home)
    os.environ["SG3D_STORE_TIMEOUT_S"] = "2"
    try:
        store = Settings(home=home).store()
    finally:
        del os.environ["SG3D_STORE_TIMEOUT_S"]
    pid = server.status().info.pid
    answer: list = []

    def run():
        try:
            store.run_raw(RUNAWAY)
            answer.append("answered")
        except Exception as exc:  # noqa: BLE001 - the store's error is the answer
            answer.append(str(exc))

    try:
        store.run_raw("RETURN 1 AS x")         # the connection is open: what follows is the statement's time
        t0 = time.monotonic()
        worker = threading.Thread(target=run, daemon=True)
        worker.start()
        worker.join(2 + 2)
        log = server.log_path.read_text(errors="replace").splitlines()
        assert answer, (f"no answer {time.monotonic() - t0:.1f} s after a statement under a 2 s limit; "
                        f"the store's log ends {[line for line in log if 'INFO' not in line][-5:]}")
        assert "2 s limit" in answer[0], answer
        time.sleep(1.0)
        before = _cpu_seconds(pid)
        time.sleep(2.0)
        assert _cpu_seconds(pid) - before < 0.5, "the daemon still computes the stopped statement"
        out = sg3d(home, "cypher", RUNAWAY)      # the CLI: the reason in one line
        assert out.returncode != 0 and "2 s limit" in out.stderr, out.stdout + out.stderr
    finally:
        store.close()
        server.stop()
