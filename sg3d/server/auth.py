"""The API token: generated once into `$SG3D_HOME/api-token`, sent by callers as
`Authorization: Bearer <token>`. A home others may write into (such as /tmp) keeps it in the
store's private directory instead (mode 0700, see `sg3d.graphdb.embedded.store_dir`): there no one
else can plant or swap it.

The file is opened without following a symlink and refused unless this user owns it and no one
else may read or write it: in a shared SG3D_HOME another user cannot plant a token."""
from __future__ import annotations

import os
import secrets
import stat
from pathlib import Path

from sg3d.core.errors import Sg3dError

TOKEN_FILE = "api-token"


class TokenError(Sg3dError, RuntimeError):
    """The token file cannot be trusted or made; the message says why and what to do."""


def token_path(home: Path) -> Path:
    """Where the token of SG3D_HOME=`home` lives: `home/api-token` when this user owns the home
    and no one else may write into it, whatever its read bits (a home made with `mkdir`, mode 755,
    included: the file itself is 0600); else in the store's private directory."""
    from sg3d.graphdb.embedded import store_dir

    home = Path(home).expanduser().resolve()
    try:
        st = os.stat(home)
    except OSError:
        return home / TOKEN_FILE          # sg3d will create the home, private
    if stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o022:
        return home / TOKEN_FILE
    return store_dir(home) / TOKEN_FILE


def _token_file(home: Path) -> Path:
    """`token_path`, once the store's directory is there (made private if sg3d makes it)."""
    from sg3d.graphdb.embedded import EmbeddedServer, EmbeddedStoreError

    server = EmbeddedServer(home)
    try:
        server.ensure_home()
    except EmbeddedStoreError as exc:
        raise TokenError(str(exc)) from None
    return token_path(home)


def read_trusted(path: Path) -> str:
    """The text of a secret file that this user owns and only it may read or write; never through
    a symlink. TokenError otherwise (nothing is chmod-ed: a file sg3d did not make is not adopted)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        reason = "it is a symbolic link" if exc.errno in (40, 31) else (exc.strerror or str(exc))
        raise TokenError(f"refusing the token file {path}: {reason}; delete it and start again") from None
    with os.fdopen(fd) as f:
        st = os.fstat(f.fileno())
        if not stat.S_ISREG(st.st_mode):
            raise TokenError(f"refusing the token file {path}: it is not a regular file")
        if st.st_uid != os.getuid():
            raise TokenError(f"refusing the token file {path}: another user owns it; delete it and start again")
        if stat.S_IMODE(st.st_mode) & 0o077:
            raise TokenError(f"refusing the token file {path}: others may read or write it (mode "
                             f"{stat.S_IMODE(st.st_mode):o}); delete it, or `chmod 600` it if you made it")
        return f.read(4096).strip()


def ensure_token(home: Path) -> str:
    """The token of this home, created (0600, 256 random bits) on first use at `token_path`; an
    existing token file is used only when it can be trusted (`read_trusted`)."""
    path = _token_file(home)
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    except FileExistsError:
        token = read_trusted(path)
        if token:
            return token
        fd = os.open(path, os.O_WRONLY | os.O_TRUNC | os.O_NOFOLLOW)
    token = secrets.token_urlsafe(32)
    with os.fdopen(fd, "w") as f:
        f.write(token + "\n")
    return token


def token_matches(expected: str, header: str | None) -> bool:
    """Constant-time check of an `Authorization: Bearer <token>` header."""
    if not header:
        return False
    scheme, _, value = header.partition(" ")
    return scheme.lower() == "bearer" and secrets.compare_digest(value.strip().encode(), expected.encode())
