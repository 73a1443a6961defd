"""The store's private folder and its secrets are never reached through a link or taken from
another user (real files in tmp_path): in a shared home (mode 1777) another user's
`ln -s <folder> <home>/sg3d-store` must not make sg3d write the store there, nor a `password`
found there become the store's root password."""
from __future__ import annotations

import os

import pytest

from sg3d.graphdb.embedded import PRIVATE_SUBDIR, EmbeddedServer, EmbeddedStoreError, check_private, read_secret
from tests.cli_helpers import one_error_line, sg3d


@pytest.fixture
def shared(tmp_path):
    """A shared home like /tmp: anyone may create entries, mode 1777."""
    home = tmp_path / "shared"
    home.mkdir()
    os.chmod(home, 0o1777)
    return home


@pytest.fixture
def planted(tmp_path):
    """A 0700 folder of this user with a `password` in it: what a link in the shared home points at."""
    target = tmp_path / "private-of-mine"
    target.mkdir(mode=0o700)
    (target / "password").write_text("chosen-by-someone-else\n")
    os.chmod(target / "password", 0o600)
    return target


def contents(folder) -> dict:
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def test_a_linked_store_folder_in_a_shared_home_is_refused(shared, planted):
    (shared / PRIVATE_SUBDIR).symlink_to(planted)
    before = contents(planted)
    server = EmbeddedServer(shared)
    assert server.home == shared / PRIVATE_SUBDIR
    for step in (server.ensure_home, server.password, server.credentials):
        with pytest.raises(EmbeddedStoreError, match="symbolic link"):
            step()
    server.mark_stopped()
    assert contents(planted) == before       # nothing written there, the password never taken


def test_sg3d_db_start_refuses_a_linked_store_folder_with_one_line(shared, planted):
    (shared / PRIVATE_SUBDIR).symlink_to(planted)
    before = contents(planted)
    out = sg3d(shared, "db", "start", timeout=120)
    line = one_error_line(out)
    assert "refusing the store directory" in line and "symbolic link" in line
    assert contents(planted) == before


def test_the_api_token_is_not_made_in_a_linked_store_folder(shared, planted):
    from sg3d.server.auth import TokenError, ensure_token

    (shared / PRIVATE_SUBDIR).symlink_to(planted)
    with pytest.raises(TokenError, match="symbolic link"):
        ensure_token(shared)
    assert "token" not in contents(planted)


@pytest.mark.parametrize("mode", [0o777, 0o770, 0o707, 0o750])
def test_a_store_folder_others_may_enter_is_refused(shared, mode):
    store = shared / PRIVATE_SUBDIR
    store.mkdir()
    os.chmod(store, mode)
    with pytest.raises(EmbeddedStoreError, match="others may enter"):
        EmbeddedServer(shared).password()
    assert not (store / "password").exists()


@pytest.mark.skipif(os.getuid() != 0, reason="giving a folder to another user needs root")
def test_a_store_folder_of_another_user_is_refused(shared, tmp_path):
    store = shared / PRIVATE_SUBDIR
    store.mkdir(mode=0o700)
    (store / "password").write_text("theirs\n")
    os.chmod(store / "password", 0o600)
    os.chown(store / "password", 65534, 65534)
    os.chown(store, 65534, 65534)
    with pytest.raises(EmbeddedStoreError, match="another user owns it"):
        EmbeddedServer(shared).password()
    # their file in a folder of mine: refused too
    os.chown(store, 0, 0)
    with pytest.raises(EmbeddedStoreError, match="another user owns it"):
        EmbeddedServer(shared).password()


def test_a_store_folder_that_is_a_file_or_missing_is_refused(tmp_path):
    (tmp_path / "f").write_text("")
    with pytest.raises(EmbeddedStoreError, match="not a directory"):
        check_private(tmp_path / "f")
    with pytest.raises(EmbeddedStoreError, match="cannot use"):
        check_private(tmp_path / "missing")


@pytest.fixture
def private(tmp_path):
    """A home private to this user: the store goes right into it."""
    home = tmp_path / "home"
    home.mkdir(mode=0o700)
    server = EmbeddedServer(home)
    assert server.home == home
    return server


def test_a_linked_password_file_is_refused_and_its_target_untouched(private, planted):
    (private.home / "password").symlink_to(planted / "password")
    with pytest.raises(EmbeddedStoreError, match="secret file .*symbolic link"):
        private.password()
    assert (planted / "password").read_text() == "chosen-by-someone-else\n"
    assert oct(os.stat(planted / "password").st_mode & 0o777) == oct(0o600)


def test_a_linked_users_file_is_refused(private, planted):
    (private.home / "users.json").symlink_to(planted / "password")
    with pytest.raises(EmbeddedStoreError, match="symbolic link"):
        private.credentials()


def test_a_password_file_others_may_write_is_refused_one_others_may_read_is_made_private(private):
    path = private.home / "password"
    path.write_text("mine\n")
    os.chmod(path, 0o622)
    with pytest.raises(EmbeddedStoreError, match="others may write"):
        private.password()
    os.chmod(path, 0o644)
    assert private.password() == "mine"
    assert os.stat(path).st_mode & 0o777 == 0o600


def test_a_password_that_is_a_folder_is_refused(private):
    (private.home / "password").mkdir()
    with pytest.raises(EmbeddedStoreError, match="not a regular file"):
        read_secret(private.home / "password")


def test_a_new_private_store_folder_gets_fresh_secrets(shared):
    server = EmbeddedServer(shared)
    server.ensure_home()
    pw = server.password()
    assert len(pw) >= 24 and server.password() == pw
    assert os.stat(server.home).st_mode & 0o777 == 0o700
    assert os.stat(server.home / "password").st_mode & 0o777 == 0o600
    creds = server.credentials()
    assert creds.writer.startswith("sg3d_writer_") and server.credentials() == creds
