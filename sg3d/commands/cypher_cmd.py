"""`sg3d cypher` and `sg3d shell`: the user's own Cypher against the same store."""
from __future__ import annotations

from typing import TYPE_CHECKING

import json
import os
from pathlib import Path

import click

from sg3d.app.errors import AppError
from sg3d.app.graph import check_statement

if TYPE_CHECKING:
    from sg3d.graphdb.protocol import GraphStore
    from sg3d.settings import Settings


def _cell(value) -> str:
    if isinstance(value, (bytes, bytearray)):
        return f"<{len(value)} bytes>"
    if isinstance(value, list) and len(value) > 8:
        return f"[{', '.join(map(_short, value[:4]))}, ... {len(value)} items]"
    if hasattr(value, "items") and not isinstance(value, dict):  # Node / Relationship
        return json.dumps({k: _short(v) for k, v in value.items()})
    return _short(value)


def _short(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, (bytes, bytearray)):
        return f"<{len(value)} bytes>"
    return str(value)


def print_result(keys, rows, as_json: bool) -> None:
    from sg3d.graphdb.values import jsonable

    if as_json:
        click.echo(json.dumps([dict(zip(keys, map(jsonable, r))) for r in rows]))
        return
    from rich.console import Console
    from rich.table import Table

    table = Table(*keys, show_lines=False)
    for r in rows:
        table.add_row(*(_cell(v) for v in r))
    console = Console()
    console.print(table)
    console.print(f"{len(rows)} row{'s' if len(rows) != 1 else ''}", style="dim")


@click.command("cypher")
@click.argument("statement")
@click.option("--param", "-p", multiple=True, metavar="NAME=JSON", help="A parameter, e.g. -p label='\"cup\"'.")
@click.option("--write", is_flag=True, help="Run in a write transaction (default: read-only).")
@click.option("--json", "as_json", is_flag=True, help="Rows as JSON.")
@click.pass_obj
def cypher_command(settings: Settings, statement: str, param, write: bool, as_json: bool) -> None:
    """Run one Cypher STATEMENT against the store and print a table.

    Read-only unless --write. Example: sg3d cypher "MATCH (o:Object) RETURN o.label, count(*)"
    """
    params = {}
    for p in param:
        name, _, raw = p.partition("=")
        try:
            params[name] = json.loads(raw)
        except ValueError:
            params[name] = raw
    from sg3d.app.stores import reader
    from sg3d.errors import UserError

    try:
        check_statement(statement, params)
    except AppError as exc:
        raise UserError(str(exc)) from None
    keys, rows = (settings.store() if write else reader(settings)).run_raw(statement, params, write=write)
    print_result(keys, rows, as_json)


def checked_runner(store: GraphStore, write: bool):
    """The shell's way to run a statement: `sg3d.app.graph.check_statement` first, then the store."""
    def run(text: str, params: dict):
        check_statement(text, params)
        return store.run_raw(text, params, write=write)
    return run


SHELL_HELP = """\
End a statement with ';' (it may span lines). Ctrl-C cancels the statement being typed or run.
  :param NAME => VALUE   set $NAME for the following statements (VALUE: JSON or a Python literal)
  :params                list the parameters      :params clear   forget them
  :help                  this text                :exit / :quit   leave (also Ctrl-D)"""


def parse_param(text: str):
    """`name => value` of `:param`, the value read as JSON, else as a Python literal."""
    import ast

    name, sep, raw = text.partition("=>")
    name, raw = name.strip().lstrip("$"), raw.strip()
    if not sep or not name.isidentifier() or not raw:
        raise ValueError("usage: :param NAME => VALUE")
    try:
        return name, json.loads(raw)
    except ValueError:
        try:
            return name, ast.literal_eval(raw)
        except (ValueError, SyntaxError):
            raise ValueError(f"cannot read the value {raw!r}: write it as JSON, e.g. 'cup' as \"cup\"") from None


class Shell:
    """The interactive loop, apart from the terminal: `read(prompt)` gives lines (raising EOFError
    at the end, KeyboardInterrupt on Ctrl-C) and `run(text, params)` runs one statement."""

    def __init__(self, run, read, echo=click.echo):
        self.run, self.read, self.echo = run, read, echo
        self.params: dict = {}
        self.buffer: list[str] = []

    def loop(self) -> None:
        while True:
            try:
                line = self.read("sg3d> " if not self.buffer else "  ... ")
            except EOFError:
                self.echo("")
                return
            except KeyboardInterrupt:
                self.buffer.clear()
                self.echo("^C statement cancelled (:exit to quit)")
                continue
            if not self.feed(line):
                return

    def feed(self, line: str) -> bool:
        """Take one line; False when the user asked to leave."""
        from neo4j.exceptions import Neo4jError

        from sg3d.errors import describe_store_error

        if not self.buffer and line.strip().startswith(":"):
            return self.command(line.strip())
        if not self.buffer and line.strip() in ("exit", "quit"):
            return False
        self.buffer.append(line)
        text = "\n".join(self.buffer).strip()
        if not text.endswith(";"):
            return True
        self.buffer.clear()
        statement = text.rstrip(";").strip()
        if not statement:
            return True
        try:
            keys, rows = self.run(statement, dict(self.params))
            print_result(keys, rows, as_json=False)
        except KeyboardInterrupt:
            self.echo("^C statement cancelled")
        except Neo4jError as exc:
            self.echo(f"error: {describe_store_error(exc)}", err=True)
        except AppError as exc:
            self.echo(f"error: {exc}", err=True)
        return True

    def command(self, text: str) -> bool:
        word, _, rest = text.partition(" ")
        if word in (":exit", ":quit"):
            return False
        if word == ":help":
            self.echo(SHELL_HELP)
        elif word == ":param":
            try:
                name, value = parse_param(rest)
            except ValueError as exc:
                self.echo(f"error: {exc}", err=True)
            else:
                self.params[name] = value
                self.echo(f"${name} = {json.dumps(value)}")
        elif word == ":params":
            if rest.strip() == "clear":
                self.params.clear()
            for name, value in sorted(self.params.items()):
                self.echo(f"${name} = {json.dumps(value)}")
        else:
            self.echo(f"error: unknown command {word}; :help lists them", err=True)
        return True


def history_path(settings: Settings) -> Path | None:
    """The shell history lives in the store's home (SG3D_HOME), or where SG3D_HISTORY says."""
    if os.environ.get("SG3D_HISTORY"):
        return Path(os.environ["SG3D_HISTORY"])
    from sg3d.graphdb.embedded import EmbeddedServer, EmbeddedStoreError

    server = EmbeddedServer(settings.embedded_home())
    try:
        server.ensure_home()
    except EmbeddedStoreError:
        return None
    return server.home / "shell_history"


@click.command()
@click.option("--write", is_flag=True, help="Allow writes (default: every statement runs read-only).")
@click.pass_obj
def shell(settings: Settings, write: bool) -> None:
    """Interactive Cypher shell with history (end a statement with ';', :help for commands,
    quit with :exit or Ctrl-D; Ctrl-C cancels the current statement)."""
    import readline

    store = settings.store() if write else settings.reader()
    history = history_path(settings)
    if history is not None:
        try:
            readline.read_history_file(history)
        except OSError:
            pass
    click.echo(f"connected to {store.uri} database {store.database}"
               f" ({'read-write' if write else 'read-only'}); end statements with ';', :help for help, :exit to quit")
    try:
        Shell(checked_runner(store, write), input).loop()
    finally:
        if history is not None:
            try:
                readline.write_history_file(history)
                os.chmod(history, 0o600)
            except OSError:
                pass


commands = [cypher_command, shell]
