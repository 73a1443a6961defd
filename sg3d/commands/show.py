"""`sg3d show --out FILE.png|.svg|.pdf|.html`: a picture of the stored scene graph."""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Optional

import click

from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf", ".html": "html", ".htm": "html"}


def parse_size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise UserError(f"--size must look like 1600x1200, not {text!r}") from None
    if not (200 <= w <= 10000 and 200 <= h <= 10000):
        raise UserError(f"--size {text}: width and height must lie in 200..10000")
    return w, h


@click.command()
@click.option("--room", default=None, help="Room name (default: every room of the building).")
@click.option("--building", default="default", show_default=True, help="Building of the room(s).")
@click.option("--out", required=True, type=click.Path(dir_okay=False, path_type=Path),
              help="Output file: .png, .svg or .pdf (top-down node-link diagram) or .html (interactive 3-D view).")
@click.option("--layout", type=click.Choice(["topdown", "spring"]), default="topdown", show_default=True,
              help="topdown: nodes at their floor position on a metre grid; spring: force layout of the relations.")
@click.option("--all-edges", is_flag=True, help="Also draw comparison edges (BIGGER_THAN, SMALLER_THAN).")
@click.option("--size", "size_text", default="1600x1200", show_default=True, metavar="WxH",
              help="PNG/SVG/PDF picture size in pixels.")
@click.option("--sequence", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="HTML: add a point cloud back-projected from a few frames of this sequence.")
@click.option("--frames", type=click.IntRange(1, 100), default=8, show_default=True,
              help="HTML: frames of --sequence to back-project.")
@click.option("--max-points", type=click.IntRange(100, 200000), default=20000, show_default=True,
              help="HTML: at most this many cloud points (one per cm cube, then subsampled).")
@click.pass_obj
def show(settings: Settings, room: Optional[str], building: str, out: Path, layout: str, all_edges: bool,
         size_text: str, sequence: Optional[Path], frames: int, max_points: int) -> None:
    """Draw the scene graph: a 2-D diagram (PNG/SVG/PDF) or a 3-D view (HTML)."""
    fmt = FORMATS.get(out.suffix.lower())
    if fmt is None:
        raise UserError(f"--out {out.name}: unknown picture type {out.suffix or '(none)'!r}; use .png, .svg, .pdf or .html")
    if sequence is not None and fmt != "html":
        raise UserError("--sequence only applies to an .html view")
    width, height = parse_size(size_text)
    if not out.resolve().parent.is_dir():
        raise UserError(f"--out {out}: the directory {out.parent} does not exist")
    from sg3d.app.errors import AppError
    from sg3d.app.scene import fetch_scene

    try:
        scene = fetch_scene(settings.reader(), building, room)
    except AppError as exc:
        raise UserError(str(exc)) from None
    title = f"{building}/{room}" if room else building
    data: str | bytes
    if fmt == "html":
        from sg3d.render.view3d import render_html

        try:
            cloud = _cloud_with_progress(sequence, frames, max_points) if sequence is not None else None
        except AppError as exc:
            raise UserError(str(exc)) from None
        data = render_html(scene, cloud=cloud, all_edges=all_edges, title=title)
    else:
        from sg3d.render.diagram import render_diagram

        data = render_diagram(scene, fmt, layout=layout, all_edges=all_edges, size=(width, height), title=title)
    try:
        if isinstance(data, bytes):
            out.write_bytes(data)
        else:
            out.write_text(data, encoding="utf-8")
    except OSError as exc:
        raise UserError(f"--out {out}: cannot write it ({exc.strerror or exc})") from None
    click.echo(f"wrote {out} ({len(scene.nodes)} nodes, {len(scene.edges)} edges)")


def _cloud_with_progress(sequence: Path, frames: int, max_points: int):
    """sg3d.app.scene.sequence_cloud with a progress bar on stderr (100 frames take ~10 s)."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
    )

    from sg3d.app.scene import sequence_cloud

    with Progress(TextColumn("[bold]point cloud"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=Console(stderr=True)) as bar:
        task = bar.add_task("point cloud", total=frames)
        return sequence_cloud(sequence, frames=frames, max_points=max_points,
                              progress=lambda done, total: bar.update(task, completed=done, total=total))


commands = [show]
