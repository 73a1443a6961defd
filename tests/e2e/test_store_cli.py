"""User errors around the store give one line and exit 2; the store's home is private without
touching a directory sg3d did not create; the shell behaves like cypher-shell."""
from __future__ import annotations

import os
import stat

import pytest
from click.testing import CliRunner

from sg3d.cli import cli
from sg3d.commands.cypher_cmd import Shell, parse_param
from sg3d.graphdb.embedded import PRIVATE_SUBDIR, EmbeddedServer, EmbeddedStoreError
from tests.cli_helpers import one_error_line, sg3d


# -- the home directory ------------------------------------------------------------------------
def test_an_existing_shared_home_is_not_chmodded_the_store_goes_into_a_private_subdirectory(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o755)
    server = EmbeddedServer(shared)
    server.ensure_home()
    assert stat.S_IMODE(shared.stat().st_mode) == 0o755
    assert server.home == shared / PRIVATE_SUBDIR
    assert stat.S_IMODE(server.home.stat().st_mode) == 0o700
    assert server.password() and stat.S_IMODE((server.home / "password").stat().st_mode) == 0o600


def test_a_home_sg3d_creates_is_private_and_used_directly(tmp_path):
    server = EmbeddedServer(tmp_path / "new" / "home")
    server.ensure_home()
    assert server.home == tmp_path / "new" / "home"
    assert stat.S_IMODE(server.home.stat().st_mode) == 0o700


def test_a_subdirectory_others_may_enter_is_refused(tmp_path):
    shared = tmp_path / "shared"
    (shared / PRIVATE_SUBDIR).mkdir(parents=True)
    shared.chmod(0o755)
    (shared / PRIVATE_SUBDIR).chmod(0o755)
    with pytest.raises(EmbeddedStoreError, match="0700"):
        EmbeddedServer(shared).ensure_home()


def test_an_unusable_home_gives_one_line_even_for_db_status(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    home = blocker / "home"
    out = sg3d(home, "db", "status")
    assert out.returncode == 0 and "not running" in out.stdout, out.stderr
    assert "cannot use the store directory" in one_error_line(sg3d(home, "cypher", "RETURN 1"))
    assert "cannot use the store directory" in one_error_line(sg3d(home, "db", "start"))


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into a read-only directory anyway")
def test_a_read_only_home_gives_one_line(tmp_path):
    home = tmp_path / "ro"
    home.mkdir(mode=0o700)
    home.chmod(0o500)
    try:
        out = sg3d(home, "db", "status")
        assert out.returncode == 0 and "Traceback" not in out.stderr
        assert "cannot use the store directory" in one_error_line(sg3d(home, "cypher", "RETURN 1"))
    finally:
        home.chmod(0o700)


# -- flags -------------------------------------------------------------------------------------
def test_show_into_a_missing_directory_is_one_line(tmp_path):
    line = one_error_line(sg3d(tmp_path / "home", "show", "--out", str(tmp_path / "nodir" / "x.png")))
    assert "does not exist" in line


def test_an_unsupported_uri_scheme_is_one_line(tmp_path):
    line = one_error_line(sg3d(tmp_path / "home", "--uri", "http://127.0.0.1:7474", "cypher", "RETURN 1"))
    assert "unsupported scheme http://" in line


@pytest.mark.parametrize("flags", [["--password", "x"], ["--user", "neo4j"], ["--database", "other"]])
def test_neo4j_flags_without_uri_are_refused_not_ignored(tmp_path, flags):
    line = one_error_line(sg3d(tmp_path / "home", *flags, "cypher", "RETURN 1"))
    assert flags[0] in line and "--uri" in line


def test_password_from_the_environment_without_uri_is_refused(tmp_path):
    line = one_error_line(sg3d(tmp_path / "home", "cypher", "RETURN 1", SG3D_PASSWORD="secret"))
    assert "--password" in line


@pytest.mark.parametrize("args", [["--room", "k", "--start", "500", "--stop", "100"],
                                  ["--room", "k", "--start", "5", "--stop", "5"],
                                  ["--room", "k", "--building", ""],
                                  ["--room", "k", "--building", "  "]])
def test_build_refuses_an_empty_frame_range_and_an_empty_building(tmp_path, args):
    one_error_line(sg3d(tmp_path / "home", "build", str(tmp_path), *args))


# -- the shell ---------------------------------------------------------------------------------
def test_param_parsing_like_cypher_shell():
    assert parse_param("label => 'cup'") == ("label", "cup")
    assert parse_param("n => 3") == ("n", 3)
    assert parse_param("$ids => [1, 2]") == ("ids", [1, 2])
    assert parse_param('m => {"a": true}') == ("m", {"a": True})
    with pytest.raises(ValueError):
        parse_param("no arrow")


def test_shell_ctrl_c_cancels_the_statement_not_the_shell_and_params_help_exit(store):
    store.run_raw("CREATE (:Object {id: 'sh/a', room: 'sh', label: 'cup'})", write=True)
    lines = iter(["MATCH (o:Object)", KeyboardInterrupt, ":param label => 'cup'", ":help",
                  "MATCH (o:Object) WHERE o.label = $label", "RETURN o.id AS id;", ":exit", "never read;"])
    ran, said = [], []

    def read(prompt):
        line = next(lines)
        if line is KeyboardInterrupt:
            raise KeyboardInterrupt
        return line

    def run(text, params):
        ran.append((text, params))
        return store.run_raw(text, params)

    Shell(run, read, echo=lambda text="", err=False: said.append(text)).loop()
    # the half-typed statement was dropped; the next one ran with the parameter; :exit left
    assert ran == [("MATCH (o:Object) WHERE o.label = $label\nRETURN o.id AS id", {"label": "cup"})]
    assert any("cancelled" in s for s in said) and any(":param NAME => VALUE" in s for s in said)
    assert next(lines) == "never read;"


def test_shell_history_lives_in_the_store_home(store, embedded_home, tmp_path):
    env = {"SG3D_HOME": str(embedded_home), "HOME": str(tmp_path), "SG3D_URI": None, "SG3D_USER": None,
           "SG3D_PASSWORD": None, "SG3D_DATABASE": None, "SG3D_HISTORY": None}
    result = CliRunner().invoke(cli, ["shell"], input="RETURN 1 AS one;\n:exit\n", env=env)
    assert result.exit_code == 0, result.output
    assert (EmbeddedServer(embedded_home).home / "shell_history").exists()
    assert not (tmp_path / ".sg3d_history").exists()
