"""Where the graph store is and how to reach it: flags first, then environment, then defaults.

Two connections per command at most: `Settings.store()` is the writer (build, merge, schema,
`--write`, `db reset`, `rooms link`); `Settings.reader()` is read-only, enforced by the store
itself (see README "Reliability and security"), for every command that only reads.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Optional
from urllib.parse import urlsplit

import click

from sg3d.errors import UserError

URI_SCHEMES = ("bolt", "bolt+s", "bolt+ssc", "neo4j", "neo4j+s", "neo4j+ssc")


def connection_options(fn):
    """The store flags every command shares (also readable from SG3D_* variables)."""
    options = [
        click.option("--uri", envvar="SG3D_URI", default=None, metavar="URI",
                     help="Bolt/Neo4j URI (bolt://, neo4j://, neo4j+s://). Default: the embedded store."),
        click.option("--user", envvar="SG3D_USER", default=None, help="User name for --uri [neo4j]."),
        click.option("--password", envvar="SG3D_PASSWORD", default=None, help="Password for --uri (prefer SG3D_PASSWORD)."),
        click.option("--read-user", envvar="SG3D_READ_USER", default=None,
                     help="For --uri: a user with a reader role, used by every read-only command."),
        click.option("--read-password", envvar="SG3D_READ_PASSWORD", default=None,
                     help="Password of --read-user (prefer SG3D_READ_PASSWORD)."),
        click.option("--database", envvar="SG3D_DATABASE", default=None, help="Database name for --uri [neo4j]."),
        click.option("--home", envvar="SG3D_HOME", default=None, type=click.Path(file_okay=False),
                     help="Data directory of the embedded store. Default: the user data directory."),
    ]
    for option in reversed(options):
        fn = option(fn)
    return fn


@dataclass(frozen=True, eq=False)  # identity hash: each command's settings cache their own stores
class Settings:
    uri: Optional[str] = None
    user: Optional[str] = None
    password: Optional[str] = None
    database: Optional[str] = None
    home: Optional[Path] = None
    read_user: Optional[str] = None
    read_password: Optional[str] = None

    @classmethod
    def from_options(cls, uri=None, user=None, password=None, database=None, home=None,
                     read_user=None, read_password=None) -> "Settings":
        return cls(uri=uri or None, user=user, password=password, database=database,
                   home=Path(home).expanduser() if home else None,
                   read_user=read_user or None, read_password=read_password)

    @property
    def embedded(self) -> bool:
        return self.uri is None

    def embedded_home(self) -> Path:
        from sg3d.graphdb.embedded import default_home

        return self.home or default_home()

    def check(self) -> None:
        """Refuse settings that would otherwise be ignored or fail deep in the driver."""
        if self.embedded:
            given = [flag for flag, value in (("--user", self.user), ("--password", self.password),
                                              ("--database", self.database), ("--read-user", self.read_user),
                                              ("--read-password", self.read_password)) if value]
            if given:
                raise UserError(f"{', '.join(given)} only apply with --uri (a Neo4j server); the embedded "
                                f"store uses its own generated users (unset SG3D_USER/SG3D_PASSWORD/"
                                f"SG3D_DATABASE/SG3D_READ_* or add --uri)")
            return
        scheme = urlsplit(self.uri or "").scheme.lower()      # not embedded: --uri is given
        if scheme not in URI_SCHEMES:
            raise UserError(f"--uri {self.uri}: unsupported scheme {scheme + '://' if scheme else '(none)'}; "
                            f"use one of {', '.join(s + '://' for s in URI_SCHEMES)}")
        if self.read_password and not self.read_user:
            raise UserError("--read-password needs --read-user")

    def _embedded_info(self):
        from sg3d.graphdb.embedded import EmbeddedServer

        return EmbeddedServer(self.embedded_home()).ensure_running()

    @functools.cache  # noqa: B019 - one Settings per command: the cache lives as long as it
    def store(self):
        """The writer store for this command (the embedded one is started on demand)."""
        from sg3d.graphdb.store import Store

        self.check()
        if self.embedded:
            info = self._embedded_info()
            return _open_embedded(lambda: Store(info.uri, info.writer_auth, info.database), self, "writer")
        return Store(self.uri, (self.user or "neo4j", self.password or ""), self.database or "neo4j")

    @functools.cache  # noqa: B019 - as store()
    def reader(self):
        """The read-only store: the embedded reader user, or with --uri the --read-user (else the
        same user, in READ transactions). sg3d's own template writes go to `store()`."""
        from sg3d.graphdb.store import Store

        self.check()
        if self.embedded:
            info = self._embedded_info()
            return _open_embedded(lambda: Store(info.uri, info.reader_auth, info.database, read_only=True,
                                                writes_via=self.store), self, "reader")
        if self.read_user:
            auth = (self.read_user, self.read_password or "")
        else:
            auth = (self.user or "neo4j", self.password or "")
        return Store(self.uri, auth, self.database or "neo4j", read_only=True, writes_via=self.store)


def _open_embedded(open_store, settings: Settings, role: str):
    from neo4j.exceptions import AuthError

    try:
        return open_store()
    except AuthError:
        from sg3d.graphdb.embedded import EmbeddedServer

        users = EmbeddedServer(settings.embedded_home()).users_path
        raise UserError(
            f"the embedded store refused sg3d's {role} login: the running store does not know the users in "
            f"{users} (was the file deleted or edited?), or repeated failed logins with that user name locked "
            f"it out for ~30 s. Recover with `sg3d db stop`: the next command restarts the store, which "
            f"re-creates sg3d's users from that file") from None
