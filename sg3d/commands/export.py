"""`sg3d export`: a room's or a building's graph as JSON (the paper's format) or GraphML."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import click

from sg3d.errors import UserError


@click.command()
@click.option("--room", default=None, help="Room name (default: every room of the building).")
@click.option("--building", default="default", show_default=True)
@click.option("--format", "fmt", type=click.Choice(["json", "graphml", "spark-dsg"]), default="json", show_default=True)
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Write to this file (default: standard output).")
@click.option("--thumbnails", is_flag=True, help="JSON: include thumbnails as base64 JPEG.")
@click.option("--histograms", is_flag=True, help="JSON: include the 512-bin HSV histograms (spark-dsg: always).")
@click.pass_obj
def export(settings, room: Optional[str], building: str, fmt: str, out: Optional[Path],
           thumbnails: bool, histograms: bool) -> None:
    """Export the scene graph: nodes with their attributes and the relation edges (json, graphml,
    or spark-dsg: the JSON of Hydra's spark_dsg.DynamicSceneGraph, see the README for the mapping)."""
    from app.errors import AppError
    from app.graph import fetch_named_graph, render_graph
    from app.stores import reader

    try:
        spark = fmt == "spark-dsg"  # loads in spark_dsg.DynamicSceneGraph.load(); re-imports losslessly
        graph = fetch_named_graph(reader(settings), building, room, thumbnails, histograms or spark,
                                  room_transforms=spark)
    except AppError as exc:
        raise UserError(str(exc)) from exc
    text = render_graph(graph, fmt)
    if out:
        out.write_text(text)
        click.echo(f"wrote {len(graph['nodes'])} nodes and {len(graph['edges'])} edges to {out}", err=True)
    else:
        click.echo(text)


commands = [export]
