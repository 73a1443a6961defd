"""Where the graph store is and how to reach it: flags first, then environment, then defaults."""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import click


def connection_options(fn):
    """The store flags every command shares (also readable from SG3D_* variables)."""
    options = [
        click.option("--uri", envvar="SG3D_URI", default=None, metavar="URI",
                     help="Bolt/Neo4j URI (bolt://, neo4j://, neo4j+s://). Default: the embedded store."),
        click.option("--user", envvar="SG3D_USER", default=None, help="User name [neo4j for --uri, root embedded]."),
        click.option("--password", envvar="SG3D_PASSWORD", default=None, help="Password (prefer SG3D_PASSWORD)."),
        click.option("--database", envvar="SG3D_DATABASE", default=None, help="Database name [neo4j / sg3d]."),
        click.option("--home", envvar="SG3D_HOME", default=None, type=click.Path(file_okay=False),
                     help="Data directory of the embedded store. Default: the user data directory."),
    ]
    for option in reversed(options):
        fn = option(fn)
    return fn


@dataclass(frozen=True)
class Settings:
    uri: Optional[str] = None
    user: Optional[str] = None
    password: Optional[str] = None
    database: Optional[str] = None
    home: Optional[Path] = None

    @classmethod
    def from_options(cls, uri=None, user=None, password=None, database=None, home=None) -> "Settings":
        return cls(uri=uri or None, user=user, password=password, database=database,
                   home=Path(home).expanduser() if home else None)

    @property
    def embedded(self) -> bool:
        return self.uri is None

    def embedded_home(self) -> Path:
        from graphdb.embedded import default_home

        return self.home or default_home()

    @functools.cache
    def store(self):
        """The open store for this command (the embedded one is started on demand)."""
        from graphdb.store import Store

        if self.embedded:
            from graphdb.embedded import EmbeddedServer

            info = EmbeddedServer(self.embedded_home()).ensure_running()
            return Store(info.uri, (info.user, info.password), info.database)
        return Store(self.uri, (self.user or "neo4j", self.password or ""), self.database or "neo4j")
