"""`sg3d eval --gt FILE --room ROOM`: how good is a stored scene graph against ground truth."""
from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import click

from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings


def _render(report: dict, names: dict[str, str], gt) -> None:
    """The report as tables; graph objects by the names `sg3d ask` uses (ids are in --json), GT
    objects by id and the annotator's name ("K14 mug")."""
    from rich.console import Console
    from rich.table import Table

    from sg3d.render.report import metric_rows

    console = Console()
    n, e = report["nodes"], report["edges"]
    summary = Table(title=f"sg3d eval: {report['room']} (tolerance {report['tolerance_m']} m)")
    summary.add_column("metric")
    summary.add_column("value", justify="right")
    for k, v in metric_rows(report):
        summary.add_row(k, v)
    console.print(summary)

    def node(p: dict) -> str:
        return names.get(p["node"], p["label"])

    def gt_name(gid: str) -> str:
        obj = gt.by_id.get(gid)
        return f"{gid} {obj.category}" if obj is not None and obj.category else gid

    detail = Table(title="nodes and objects", show_lines=False)
    for col in ("kind", "object", "label", "GT", "distance m"):
        detail.add_column(col)
    for p in n["pairs"]:
        detail.add_row("match", node(p), p["label"], gt_name(p["gt"]), f"{p['distance']:.2f}")
    for p in n["duplicates"]:
        detail.add_row("[yellow]duplicate", node(p), p["label"], gt_name(p["gt"]), f"{p['distance']:.2f}")
    for p in n["spurious"]:
        near = f"(nearest {gt_name(p['nearest_gt'])})" if "nearest_gt" in p else ""
        detail.add_row("[red]spurious", node(p), p["label"], near,
                       f"{p['nearest_distance']:.2f}" if "nearest_distance" in p else "")
    for g in n["missing"]:
        detail.add_row("[red]missing" + ("" if g["sure"] else " (unsure)"), "", g["coco"], gt_name(g["gt"]), "")
    console.print(detail)
    if n["not_detectable"]:
        console.print("not detectable by a COCO detector: "
                      + ", ".join(f"{g['gt']} {g['category']}" for g in n["not_detectable"]), style="dim")
    if e["per_type"]:
        types = Table(title="edges by type")
        for col in ("type", "GT checked", "found", "graph (judged)", "correct"):
            types.add_column(col, justify="right" if col != "type" else "left")
        for t, c in e["per_type"].items():
            types.add_row(t, str(c["gt"]), str(c["found"]), str(c["graph"]), str(c["correct"]))
        console.print(types)
    vqa = report.get("vqa")
    if vqa is not None and vqa["questions"]:
        q = Table(title="VQA (sure questions)")
        for col in ("status", "question", "expected", "got"):
            q.add_column(col, overflow="fold")
        style = {"right": "green", "wrong": "red", "unsupported": "dim", "not scorable": "yellow"}
        for row in vqa["questions"]:
            q.add_row(f"[{style[row['status']]}]{row['status']}", row["question"], str(row["expected"]),
                      str(row.get("answer", row.get("got", row.get("reason", "")))))
        console.print(q)


@click.command("eval")
@click.option("--gt", "gt_path", required=True, type=click.Path(dir_okay=False, path_type=Path),
              help="Ground-truth JSON (objects, relations, questions).")
@click.option("--room", required=True, help="Room name as given to `sg3d build`.")
@click.option("--building", default="default", show_default=True, help="Building of the room.")
@click.option("--tolerance", type=click.FloatRange(min=0, min_open=True), default=None, metavar="M",
              help="Greatest node-to-GT distance in metres for a match [0.5; GT positions are approximate].")
@click.option("--no-vqa", is_flag=True, help="Skip the questions.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable report on stdout.")
@click.option("--report", "report_dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Also write DIR/report.md and DIR/report.html: metrics, node, edge and VQA tables, and the graph picture coloured by match.")
@click.pass_obj
def eval_command(settings: Settings, gt_path: Path, room: str, building: str, tolerance: Optional[float],
                 no_vqa: bool, as_json: bool, report_dir: Optional[Path]) -> None:
    """Compare the scene graph of ROOM with ground truth: nodes, edges and question answers."""
    from sg3d.evaluation.evaluate import evaluate
    from sg3d.evaluation.ground_truth import load_gt
    from sg3d.evaluation.matching import DEFAULT_TOLERANCE
    from sg3d.graphdb.values import room_id

    try:
        gt = load_gt(gt_path)
    except ValueError as exc:
        raise UserError(str(exc)) from None
    store = settings.reader()
    rid = room_id(building, room)
    if not store.read("eval_room_exists", room=rid):
        raise UserError(f"no room {room!r} in building {building!r} (build it with `sg3d build`)")
    from sg3d.evaluation.ground_truth import outside_extent

    outside, placed = outside_extent(gt, store.read("eval_objects", room=rid))
    if placed and outside > placed / 2:
        click.echo(f"warning: {outside} of {placed} ground-truth objects lie outside the extent of room {rid!r}; "
                   f"is {gt_path.name} the ground truth of another sequence?", err=True)
    report = evaluate(store, gt, rid, room=room, building=building,
                      tolerance=DEFAULT_TOLERANCE if tolerance is None else tolerance, with_vqa=not no_vqa)
    if report_dir is not None:
        from sg3d.app.scene import fetch_scene
        from sg3d.render.report import write_report

        written = write_report(report_dir, report, fetch_scene(store, building, room), gt, room)
        click.echo("wrote " + ", ".join(str(p) for p in written), err=as_json)   # stdout holds only the JSON
    if as_json:
        click.echo(json.dumps(report))
    else:
        from sg3d.app.errors import NotFound
        from sg3d.app.graph import fetch_named_graph

        try:
            names = {n.id: n.name or n.id for n in fetch_named_graph(store, building, room).nodes}
        except NotFound:
            names = {}
        _render(report, names, gt)


commands = [eval_command]
