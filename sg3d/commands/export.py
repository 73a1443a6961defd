"""`sg3d export`: a room's or a building's graph as JSON (the paper's format) or GraphML."""
from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import click

from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings


@click.command()
@click.option("--room", default=None, help="Room name (default: every room of the building).")
@click.option("--building", default="default", show_default=True, help="Building of the room(s).")
@click.option("--format", "fmt", type=click.Choice(["json", "graphml", "spark-dsg", "3dssg"]), default="json",
              show_default=True, help="json: the paper's form; graphml; spark-dsg: Hydra's JSON (--out must end "
                                      "in .json); 3dssg: objects.json + relationships.json.")
@click.option("--out", type=click.Path(path_type=Path), default=None,
              help="Write to this file, or '-' for standard output (default: standard output when it is a "
                   "pipe or file; on a terminal only a summary); 3dssg: a folder for objects.json and "
                   "relationships.json.")
@click.option("--thumbnails", is_flag=True, help="--format json only: include thumbnails as base64 JPEG.")
@click.option("--histograms", is_flag=True,
              help="--format json only: include the 512-bin HSV histograms (spark-dsg has them always).")
@click.pass_obj
def export(settings: Settings, room: Optional[str], building: str, fmt: str, out: Optional[Path],
           thumbnails: bool, histograms: bool) -> None:
    """Export the scene graph: nodes with their attributes and the relation edges (json, graphml,
    spark-dsg: the JSON of Hydra's spark_dsg.DynamicSceneGraph, or 3dssg: the 3DSSG benchmark's
    objects.json + relationships.json; see the README for the mappings)."""
    from sg3d.app.errors import AppError
    from sg3d.app.graph import fetch_named_graph, render_graph, write_3dssg
    from sg3d.app.stores import reader

    to_stdout = out is not None and str(out) == "-"
    out = None if to_stdout else out
    _check_options(fmt, out, thumbnails, histograms)   # before the store starts
    try:
        spark = fmt == "spark-dsg"  # loads in spark_dsg.DynamicSceneGraph.load(); re-imports losslessly
        graph = fetch_named_graph(reader(settings), building, room, thumbnails, histograms or spark,
                                  room_transforms=spark)
    except AppError as exc:
        raise UserError(str(exc)) from exc
    if fmt == "3dssg" and out:
        try:
            n_obj, n_rel = write_3dssg(graph, out)
        except AppError as exc:
            raise UserError(str(exc)) from exc
        click.echo(f"wrote {n_obj} objects and {n_rel} relationships to {out}/objects.json, relationships.json")
        return
    if out and out.is_dir():
        raise UserError(f"--out {out} is a folder; give a file name")
    text = render_graph(graph, fmt)
    if out:
        out.write_text(text)
        click.echo(f"wrote {len(graph.nodes)} nodes and {len(graph.edges)} edges to {out}")
    elif to_stdout or not sys.stdout.isatty():
        click.echo(text)
    else:   # a terminal would get one line of many kilobytes
        click.echo(f"{len(graph.nodes)} nodes and {len(graph.edges)} edges ({fmt}, {len(text):,} characters); "
                   f"add --out FILE to write them, or --out - to print them here")


def _check_options(fmt: str, out: Optional[Path], thumbnails: bool, histograms: bool) -> None:
    """Refuse options the format would ignore, and a spark-dsg file name spark_dsg cannot load
    (it picks its codec by extension: no extension means binary, '.spark-dsg' is refused)."""
    if thumbnails and fmt != "json":
        raise UserError(f"--thumbnails only applies to --format json, not {fmt}")
    if histograms and fmt not in ("json", "spark-dsg"):
        raise UserError(f"--histograms only applies to --format json (spark-dsg has them always), not {fmt}")
    if fmt == "spark-dsg" and out is not None and out.suffix != ".json" and not out.is_dir():
        raise UserError(f"--out {out}: a spark-dsg file must end in .json, or spark_dsg (and `sg3d import`) "
                        f"cannot load it")


commands = [export]
