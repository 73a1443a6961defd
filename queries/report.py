"""`sg3d eval --report DIR`: the evaluation as report.md and report.html with a picture.

The picture is the top-down graph (queries/render.py) with each node filled by its evaluation
status (matched green, spurious red, duplicate orange) and each missing GT object drawn as a
hollow marker at its annotated position, so a reader sees at once where the graph is wrong.
"""
from __future__ import annotations

import base64
import html
from pathlib import Path
from typing import Optional

import numpy as np

PICTURE = "graph.png"


def pct(v: Optional[float]) -> str:
    return "-" if v is None else f"{100 * v:.1f}%"


def metric_rows(report: dict) -> list[tuple[str, str]]:
    n, e = report["nodes"], report["edges"]
    rows = [
        ("graph nodes", n["graph_nodes"]),
        ("GT objects (COCO, located)", f"{n['gt_detectable']} of {n['gt_objects']}"),
        ("matched nodes", n["matched"]),
        ("node precision", pct(n["precision"])),
        ("node recall", pct(n["recall"])),
        ("node recall, sure objects", f"{pct(n['recall_sure'])} of {n['gt_sure']}"),
        ("unsure objects found", f"{n['unsure_found']} of {n['gt_unsure']}"),
        ("spurious nodes", len(n["spurious"])),
        ("duplicate nodes", len(n["duplicates"])),
        ("missing nodes", len(n["missing"])),
        ("not detectable by a COCO detector", len(n["not_detectable"])),
        ("no GT position", len(n["unlocated"])),
        ("GT relations checked", f"{e['checked']} of {e['gt_relations']}"),
        ("edge precision", pct(e["precision"])),
        ("edge recall (checked)", pct(e["recall"])),
        ("edge recall (all GT)", pct(e["recall_all"])),
        ("spurious edges (matched nodes)", len(e["spurious"])),
        ("missed edges (checked)", len(e["missed"])),
    ]
    vqa = report.get("vqa")
    if vqa is not None:
        rows += [("VQA accuracy (scored)", f"{pct(vqa['accuracy'])} of {vqa['scored']}"),
                 ("VQA accuracy (all sure)", f"{pct(vqa['accuracy_all_sure'])} of {vqa['sure_questions']}"),
                 ("VQA unsupported", sum(q["status"] == "unsupported" for q in vqa["questions"]))]
    return [(k, str(v)) for k, v in rows]


def node_status(report: dict) -> dict[str, str]:
    n = report["nodes"]
    status = {p["node"]: "matched" for p in n["pairs"]}
    status.update({p["node"]: "spurious" for p in n["spurious"]})
    status.update({p["node"]: "duplicate" for p in n["duplicates"]})
    return status


def missing_markers(report: dict, gt, scene, room: str):
    """Hollow markers for the missing GT objects, projected like the nodes of `room`."""
    from queries.render import Marker, project_points, room_up

    up = room_up(scene, room)
    out = []
    for g in report["nodes"]["missing"]:
        obj = gt.by_id.get(g["gt"])
        if obj is None or obj.position is None:
            continue
        xy = project_points(np.array([obj.position]), up)[0]
        out.append(Marker(f"{g['coco']} {g['gt']}", xy))
    return out


def write_report(out_dir: Path, report: dict, scene, gt, room: str, *, width: int = 1600,
                 height: int = 1200) -> list[Path]:
    """Write DIR/graph.png, DIR/report.md, DIR/report.html; returns their paths."""
    from queries.render import render

    out_dir.mkdir(parents=True, exist_ok=True)
    markers = missing_markers(report, gt, scene, room)
    png = render(scene, "png", width=width, height=height, status=node_status(report),
                 markers=markers, title=f"eval {report['room']}")
    (out_dir / PICTURE).write_bytes(png)
    rows = metric_rows(report)
    n = report["nodes"]
    from queries.render import display_names

    names = display_names(scene.nodes, scene.edges)     # the names the picture, ask and plan use

    def details() -> list[tuple[str, list[str]]]:
        return [
            ("Duplicate nodes", [f"{names.get(p['node'], p['label'])} repeats {p['gt']}, {p['distance']:.2f} m"
                                 for p in n["duplicates"]]),
            ("Spurious nodes", [f"{names.get(p['node'], p['label'])}"
                                + (f", nearest GT {p['nearest_gt']} at {p['nearest_distance']:.2f} m"
                                   if "nearest_gt" in p else "") for p in n["spurious"]]),
            ("Missing GT objects", [f"{g['gt']} {g['coco']}" + ("" if g["sure"] else " (unsure)")
                                    for g in n["missing"]]),
        ]

    md = [f"# sg3d eval: {report['room']}", "",
          f"Match tolerance {report['tolerance_m']} m.", "",
          "| metric | value |", "|---|---:|"]
    md += [f"| {k} | {v} |" for k, v in rows]
    md += ["", f"![graph: matched green, spurious red, duplicate orange, missing GT hollow]({PICTURE})", "",
           "Top-down view: nodes at their floor position (relaxed so labels do not overlap); "
           "green = matched a GT object, red = spurious, orange = duplicate of a matched object, "
           "hollow red rings = GT objects the graph lacks, at their annotated position.", ""]
    for title, items in details():
        md += [f"## {title} ({len(items)})", ""] + [f"- {i}" for i in items] + [""]
    (out_dir / "report.md").write_text("\n".join(md), encoding="utf-8")

    esc = html.escape
    img = base64.b64encode(png).decode()
    page = ["<!DOCTYPE html>", '<html><head><meta charset="utf-8">',
            f"<title>sg3d eval {esc(report['room'])}</title>",
            "<style>body{font:14px sans-serif;margin:2em}table{border-collapse:collapse}"
            "td,th{border:1px solid #ccc;padding:3px 8px}td.v{text-align:right}img{max-width:100%}</style>",
            "</head><body>", f"<h1>sg3d eval: {esc(report['room'])}</h1>",
            f"<p>Match tolerance {report['tolerance_m']} m.</p>",
            "<table><tr><th>metric</th><th>value</th></tr>"]
    page += [f"<tr><td>{esc(k)}</td><td class=\"v\">{esc(v)}</td></tr>" for k, v in rows]
    page += ["</table>",
             f'<p><img alt="scene graph coloured by evaluation status" src="data:image/png;base64,{img}"></p>',
             "<p>Green: matched; red: spurious; orange: duplicate; hollow red ring: missing GT object.</p>"]
    for title, items in details():
        page += [f"<h2>{esc(title)} ({len(items)})</h2>", "<ul>"] + [f"<li>{esc(i)}</li>" for i in items] + ["</ul>"]
    page.append("</body></html>")
    (out_dir / "report.html").write_text("\n".join(page), encoding="utf-8")
    return [out_dir / PICTURE, out_dir / "report.md", out_dir / "report.html"]
