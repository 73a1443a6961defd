"""`sg3d import --format spark-dsg FILE`: another tool's scene graph (Hydra's spark_dsg) into the store."""
from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import click

from sg3d.commands.names import checked_name
from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings


@click.command("import")
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(["spark-dsg"]), default="spark-dsg", show_default=True,
              help="File format: spark_dsg JSON (Hydra, Clio, `sg3d export --format spark-dsg`).")
@click.option("--building", default=None, callback=checked_name,
              help="Building to merge into (default: the file's building, else 'default').")
@click.option("--room", default=None, callback=checked_name,
              help="Merge every object into this room (default: one room per room of the file).")
@click.option("--json", "as_json", is_flag=True, help="Print the merge report as JSON.")
@click.pass_obj
def import_command(settings: Settings, file: Path, fmt: str, building: Optional[str], room: Optional[str], as_json: bool) -> None:
    """Merge a spark_dsg scene graph (Hydra, Clio; or `sg3d export --format spark-dsg`) into the
    store: objects with their labels, positions, boxes and colours, the relations our export wrote.
    Importing the same file again merges nothing."""
    from sg3d.app.errors import AppError
    from sg3d.app.graph import import_spark_dsg

    if room is not None and (not room.strip() or "/" in room):
        raise UserError("--room must be non-empty and contain no '/'")
    try:
        report = import_spark_dsg(settings.store(), file, building, room)
    except AppError as exc:
        raise UserError(str(exc)) from exc
    if as_json:
        click.echo(json.dumps(report))
        return
    for r in report["rooms"]:
        what = "already imported, nothing merged" if r["skipped"] else (
            f"{r['created']} new objects, {r['updated']} updated, {r['relations']} relations")
        click.echo(f"{r['room']}: {what}; room holds {r['room_objects']} objects")


commands = [import_command]
