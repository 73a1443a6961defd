"""Failed logins by other local processes must not lock sg3d out of its own store.

ArcadeDB refuses a user name for ~30 s after repeated failed logins (Bolt or HTTP). sg3d logs in
as its own users, whose names carry a random suffix kept in a 0600 file, so a process that
cannot read that file cannot name them; when sg3d is refused anyway, the message names the causes
and the recovery."""
from __future__ import annotations

import base64
import json
import urllib.error
import urllib.request

from click.testing import CliRunner
from neo4j import GraphDatabase
from neo4j.exceptions import AuthError

from sg3d.cli import cli
from sg3d.graphdb.embedded import EmbeddedServer

GUESSED = ["root", "admin", "neo4j", "sg3d", "reader", "writer", "sg3d_reader", "sg3d_writer"]
ENV = {"SG3D_URI": None, "SG3D_USER": None, "SG3D_PASSWORD": None, "SG3D_DATABASE": None}


def fail_logins(info, names, times=7):
    for name in names:
        driver = GraphDatabase.driver(info.uri, auth=(name, "wrong-password"))
        for _ in range(times):
            try:
                driver.verify_connectivity()
            except AuthError:
                pass
        driver.close()
        token = base64.b64encode(f"{name}:wrong-password".encode()).decode()
        for _ in range(times):
            request = urllib.request.Request(f"http://127.0.0.1:{info.http_port}/api/v1/server",
                                             headers={"Authorization": f"Basic {token}"})
            try:
                urllib.request.urlopen(request, timeout=5).read()
            except (urllib.error.HTTPError, OSError):
                pass


def test_failed_logins_of_other_processes_do_not_lock_sg3d_out(store, embedded_home):
    info = EmbeddedServer(embedded_home).status().info
    fail_logins(info, GUESSED)
    # the administrator's own login is indeed locked now: the attack took effect
    root = GraphDatabase.driver(info.uri, auth=("root", EmbeddedServer(embedded_home).password()))
    try:
        root.verify_connectivity()
        root_locked = False
    except AuthError:
        root_locked = True
    finally:
        root.close()
    assert root_locked
    env = dict(ENV, SG3D_HOME=str(embedded_home))
    read = CliRunner().invoke(cli, ["cypher", "RETURN 1 AS one", "--json"], env=env)
    assert read.exit_code == 0 and json.loads(read.output) == [{"one": 1}], read.output
    write = CliRunner().invoke(cli, ["cypher", "--write", "MERGE (x:Probe {id: 'lockout'}) RETURN 1 AS one"], env=env)
    assert write.exit_code == 0, write.output


def test_a_refused_login_says_why_and_how_to_recover(store, embedded_home):
    server = EmbeddedServer(embedded_home)
    saved = server.users_path.read_text()
    creds = json.loads(saved)
    try:
        server.users_path.write_text(json.dumps(dict(creds, reader_password="not-the-password")))
        result = CliRunner().invoke(cli, ["cypher", "RETURN 1"], env=dict(ENV, SG3D_HOME=str(embedded_home)))
        assert result.exit_code == 2
        line = result.output.strip()
        assert len(line.splitlines()) == 1
        assert "users.json" in line and "sg3d db stop" in line and "locked" in line
    finally:
        server.users_path.write_text(saved)
