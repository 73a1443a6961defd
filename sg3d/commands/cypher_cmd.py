"""`sg3d cypher` and `sg3d shell`: the user's own Cypher against the same store."""
from __future__ import annotations

import json
import os
from pathlib import Path

import click


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
    from app.graph import jsonable

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
def cypher_command(settings, statement: str, param, write: bool, as_json: bool) -> None:
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
    from app.stores import reader

    keys, rows = (settings.store() if write else reader(settings)).run_raw(statement, params, write=write)
    print_result(keys, rows, as_json)


@click.command()
@click.option("--write", is_flag=True, help="Allow writes (default: every statement runs read-only).")
@click.pass_obj
def shell(settings, write: bool) -> None:
    """Interactive Cypher shell with history (end a statement with ';', quit with :exit or Ctrl-D)."""
    import readline

    from neo4j.exceptions import Neo4jError

    history = Path(os.environ.get("SG3D_HISTORY", Path.home() / ".sg3d_history"))
    try:
        readline.read_history_file(history)
    except OSError:
        pass
    store = settings.store()
    click.echo(f"connected to {store.uri} database {store.database}"
               f" ({'read-write' if write else 'read-only'}); end statements with ';', :exit to quit")
    buffer: list[str] = []
    try:
        while True:
            try:
                line = input("sg3d> " if not buffer else "  ... ")
            except EOFError:
                click.echo()
                break
            if not buffer and line.strip() in (":exit", ":quit", "exit", "quit"):
                break
            buffer.append(line)
            text = "\n".join(buffer).strip()
            if not text.endswith(";"):
                continue
            buffer.clear()
            try:
                keys, rows = store.run_raw(text.rstrip(";"), write=write)
                print_result(keys, rows, as_json=False)
            except Neo4jError as exc:
                click.echo(f"error: {exc.code}: {(exc.message or str(exc)).splitlines()[0]}", err=True)
    finally:
        try:
            readline.write_history_file(history)
        except OSError:
            pass


commands = [cypher_command, shell]
