"""The `sg3d` command line: a click group whose commands live in `sg3d/commands/`.

Each module in `sg3d.commands` exposes `commands`, a list of click commands; they are
registered here so that adding a command never means editing this file.
"""
from __future__ import annotations

import importlib
import pkgutil
import sys

import click

import sg3d.commands
from sg3d import __version__
from sg3d.settings import connection_options


@click.group(context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
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


def _register() -> None:
    for info in sorted(pkgutil.iter_modules(sg3d.commands.__path__), key=lambda i: i.name):
        module = importlib.import_module(f"sg3d.commands.{info.name}")
        for command in getattr(module, "commands", []):
            cli.add_command(command)


_register()


def main() -> None:
    from sg3d.errors import run_cli

    sys.exit(run_cli(cli))
