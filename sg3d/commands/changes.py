"""`sg3d changes`: what the room's re-scans moved, added and removed."""
from __future__ import annotations

from typing import TYPE_CHECKING

import json

import click

if TYPE_CHECKING:
    from sg3d.settings import Settings


def _where(o: dict) -> str:
    return f"({o['x']:.2f}, {o['y']:.2f}, {o['z']:.2f})"


@click.command()
@click.option("--room", required=True, help="Room name.")
@click.option("--building", default="default", show_default=True, help="The building the room belongs to.")
@click.option("--since", default=None, metavar="SCAN",
              help="Changes of the scans after this scan id (default: the room's last scan).")
@click.option("--json", "as_json", is_flag=True,
              help="JSON: moved, added, removed (each object: id, name, label, x, y, z; moved: from).")
@click.pass_obj
def changes(settings: Settings, room: str, building: str, since, as_json: bool) -> None:
    """What moved, appeared and disappeared in ROOM at its last scan (or since scan SCAN).

    Every `sg3d build` and every `POST /ingest` batch is a scan; `sg3d build --json` prints its id.
    """
    from sg3d.app.changes import room_changes
    from sg3d.app.errors import AppError
    from sg3d.app.stores import reader
    from sg3d.errors import UserError

    try:
        result = room_changes(reader(settings), room, building, since)
    except AppError as exc:
        raise UserError(str(exc)) from exc
    if as_json:
        click.echo(json.dumps(result, indent=2))
        return
    click.echo(f"scans: {', '.join(result['scans']) or 'none after ' + str(since)}")
    for o in result["moved"]:
        click.echo(f"moved    {o['name']}: {_where(o['from'])} -> {_where(o)}")
    for o in result["added"]:
        click.echo(f"added    {o['name']} at {_where(o)}")
    for o in result["removed"]:
        click.echo(f"removed  {o['name']} (was at {_where(o)})")
    if not (result["moved"] or result["added"] or result["removed"]):
        click.echo("no changes")


commands = [changes]
