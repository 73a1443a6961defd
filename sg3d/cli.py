"""The `sg3d` command line: a click group whose commands live in `sg3d/commands/`.

Each module in `sg3d.commands` exposes `commands`, a list of click commands; they are
registered here so that adding a command never means editing this file.

The modules are imported lazily: `sg3d ask ...` imports `sg3d.commands.ask` only (a module named
after the command, or after it with `_cmd`), not every command's imports; a command whose module
is named otherwise (`shell`, `mcp`), and `sg3d --help`, import them all.
"""
from __future__ import annotations

import importlib
import pkgutil
import sys
from types import FrameType
from typing import Optional

import click

import sg3d.commands
from sg3d import __version__
from sg3d.settings import connection_options


class LazyGroup(click.Group):
    """A group that imports a command's module when the command is asked for."""

    _all_loaded = False

    def _load(self, module_name: str) -> None:
        module = importlib.import_module(f"sg3d.commands.{module_name}")
        for command in getattr(module, "commands", []):
            if command.name not in self.commands:
                self.add_command(command)

    def _load_all(self) -> None:
        if not self._all_loaded:
            for info in sorted(pkgutil.iter_modules(sg3d.commands.__path__), key=lambda i: i.name):
                self._load(info.name)
            self._all_loaded = True

    def get_command(self, ctx: click.Context, cmd_name: str) -> Optional[click.Command]:
        if cmd_name not in self.commands and not self._all_loaded:
            modules = {info.name for info in pkgutil.iter_modules(sg3d.commands.__path__)}
            for guess in (cmd_name.replace("-", "_"), f"{cmd_name.replace('-', '_')}_cmd"):
                if guess in modules:
                    self._load(guess)
            if cmd_name not in self.commands:
                self._load_all()
        return self.commands.get(cmd_name)

    def list_commands(self, ctx: click.Context) -> list[str]:
        self._load_all()
        return sorted(self.commands)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
@click.version_option(__version__, prog_name="sg3d")
@connection_options
@click.pass_context
def cli(ctx: click.Context, **conn) -> None:
    """sg3d: build 3-D scene graphs from RGB-D scans, store them in a graph database, ask
    questions and plan tasks with them.

    With no --uri the embedded store (ArcadeDB over Bolt, started on demand under the user data
    directory) is used; with --uri any Neo4j 5 server is used through the same driver and Cypher.
    """
    from sg3d.settings import Settings

    ctx.obj = Settings.from_options(**conn)


class _DriverWithoutPandas:
    """An import hook that refuses pandas and pyarrow to the neo4j driver's probe for optional
    dependencies (`neo4j._optional_deps`), and to nothing else.

    The driver imports pandas whenever it is installed, only to accept pandas values as query
    parameters; that import is a fifth of a cold `sg3d ask` (0.2 s), and no sg3d code hands the
    driver a pandas value. The `sg3d` command installs it for its own process only (`main`): code
    that imports sg3d as a library gets the driver as it comes, and pandas itself stays importable
    in the command's process (by the trajectory evaluation, say). Where pandas is already imported
    the hook is never asked."""

    blocked = ("pandas", "pyarrow")

    def find_spec(self, name: str, path=None, target=None):
        if name.partition(".")[0] in self.blocked:
            frame: Optional[FrameType] = sys._getframe(1)
            while frame is not None:
                if frame.f_globals.get("__name__") == "neo4j._optional_deps":
                    raise ModuleNotFoundError(f"{name} is not offered to the neo4j driver by sg3d", name=name)
                frame = frame.f_back
        return None


def main() -> None:
    from sg3d.errors import run_cli

    if not any(isinstance(f, _DriverWithoutPandas) for f in sys.meta_path):
        sys.meta_path.insert(0, _DriverWithoutPandas())
    sys.exit(run_cli(cli))
