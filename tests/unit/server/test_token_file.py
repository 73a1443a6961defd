"""The API token lives in a folder only this user may write into (the home, or in a home others
may write into the store's private directory) and is never taken from a file another user could
have planted (real files, real modes, no mocks)."""
from __future__ import annotations

import os
import stat

import pytest


@pytest.fixture
def shared_home(tmp_path):
    """A home like /tmp: everyone may write into it (sticky)."""
    home = tmp_path / "shared"
    home.mkdir()
    home.chmod(0o1777)
    return home


def test_a_token_planted_in_a_shared_home_is_not_used(shared_home):
    from sg3d.server.auth import ensure_token, token_path

    planted = shared_home / "api-token"
    planted.write_text("planted-token\n")
    planted.chmod(0o644)
    token = ensure_token(shared_home)
    assert token != "planted-token"
    path = token_path(shared_home)
    assert path.parent.name == "sg3d-store" and path.read_text().strip() == token
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert stat.S_IMODE(path.parent.stat().st_mode) == 0o700
    assert stat.S_IMODE(planted.stat().st_mode) == 0o644      # nothing of it was touched


def test_a_symlinked_token_is_refused_and_its_target_untouched(tmp_path):
    from sg3d.server.auth import TokenError, ensure_token, token_path

    home = tmp_path / "home"
    ensure_token(home)
    path = token_path(home)
    path.unlink()
    target = tmp_path / "victim"
    target.write_text("secret of someone\n")
    target.chmod(0o644)
    os.symlink(target, path)
    with pytest.raises(TokenError, match="symbolic link"):
        ensure_token(home)
    assert stat.S_IMODE(target.stat().st_mode) == 0o644


def test_a_token_others_may_read_is_refused(tmp_path):
    from sg3d.server.auth import TokenError, ensure_token, token_path

    home = tmp_path / "home"
    ensure_token(home)
    token_path(home).chmod(0o644)
    with pytest.raises(TokenError, match="others may read"):
        ensure_token(home)


def test_serve_with_a_planted_token_says_so_in_one_line(tmp_path):
    from click.testing import CliRunner

    from sg3d.cli import cli
    from sg3d.graphdb.embedded import free_port
    from sg3d.server.auth import ensure_token, token_path

    home = tmp_path / "home"
    ensure_token(home)
    token_path(home).chmod(0o666)
    r = CliRunner().invoke(cli, ["--home", str(home), "serve", "--port", str(free_port())])
    assert r.exit_code == 2 and "refusing the token file" in r.output
