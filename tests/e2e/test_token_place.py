"""The API token has one documented place, `$SG3D_HOME/api-token`, whether sg3d made the home or
the user did (`mkdir`, mode 755) beforehand; only a home others may write into (such as /tmp,
mode 1777) keeps it in the store's private folder, where no one else can plant or swap it. Real
files in tmp_path; `sg3d serve` says where it is."""
from __future__ import annotations

import os
import stat

import pytest

from sg3d.graphdb.embedded import PRIVATE_SUBDIR


@pytest.mark.parametrize("made_by", ["sg3d", "mkdir 755", "mkdir 700"])
def test_the_token_is_in_the_home_whoever_made_it(tmp_path, made_by):
    from sg3d.server.auth import ensure_token, token_path

    home = tmp_path / "home"
    if made_by != "sg3d":
        home.mkdir()
        os.chmod(home, 0o755 if made_by == "mkdir 755" else 0o700)
    token = ensure_token(home)
    assert token_path(home) == home.resolve() / "api-token"
    assert (home / "api-token").read_text().strip() == token
    assert stat.S_IMODE((home / "api-token").stat().st_mode) == 0o600
    assert not (home / PRIVATE_SUBDIR / "api-token").exists()
    assert ensure_token(home) == token                         # made once, then read back


def test_a_home_others_may_write_into_keeps_the_token_in_the_private_folder(tmp_path):
    from sg3d.server.auth import ensure_token, token_path

    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o1777)
    token = ensure_token(shared)
    assert token_path(shared) == shared.resolve() / PRIVATE_SUBDIR / "api-token"
    assert (shared / PRIVATE_SUBDIR / "api-token").read_text().strip() == token
    assert not (shared / "api-token").exists()
