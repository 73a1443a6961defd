"""`sg3d eval --report DIR`: the evaluation as report.md and report.html with a picture.

The picture is the top-down diagram (`sg3d.render.diagram`) with each node filled by its evaluation
status (matched green, spurious red, duplicate orange) and each missing GT object drawn as a
hollow marker at its annotated position. The tables name graph objects as `sg3d ask` does
(sg3d/queries/naming.py, through sg3d.app.scene.fetch_scene): "white cup", "chair 2", never an id; GT
objects keep their ground-truth ids, which is what a reader checks them against.
"""
from __future__ import annotations

import base64
import html
from pathlib import Path
from typing import Optional

from sg3d.core.stored import Scene

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
        ("colour agreement (matched)", f"{pct(n['colour']['agreement'])} ({n['colour']['agree']} of {n['colour']['with_colour']})"),
        ("missing nodes", len(n["missing"])),
        ("not detectable by a COCO detector", len(n["not_detectable"])),
        ("no GT position", len(n["unlocated"])),
    ]
    o, st = report.get("objects"), report.get("structure")
    if o is not None:
        rows += [
            ("every object: nodes (unnamed)", f"{o['nodes']} ({o['unnamed_nodes']})"),
            ("every object: GT located", o["gt_located"]),
            ("every object: matched", o["matched"]),
            ("every object: precision", pct(o["precision"])),
            ("every object: recall", pct(o["recall"])),
            ("every object: duplicates", o["duplicates"]),
        ]
    if st is not None:
        rows += [("structure: floor, walls", f"{'yes' if st['floor'] else 'no'}, {st['walls']}"),
                 ("structure: surfaces", ", ".join(st["surfaces"]) or "none")]
        rows += [(f"height of {f['label']} ({f['gt']})", f"{f['height_m']:.2f} m") for f in st["furniture_heights"]]
    rows += [
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


def missing_markers(report: dict, gt, room: str):
    """Hollow markers for the missing GT objects at their annotated (world) positions."""
    from sg3d.render.diagram import Marker

    out = []
    for g in report["nodes"]["missing"]:
        obj = gt.by_id.get(g["gt"])
        if obj is not None and obj.position is not None:
            out.append(Marker(f"{g['coco']} {g['gt']}", obj.position, room))
    return out


def tables(report: dict, names: dict[str, str], gt=None) -> list[tuple[str, list[str], list[list[str]]]]:
    """(title, header, rows) of every table of the report: graph objects by their readable names,
    GT objects by id and the annotator's name ("K14 mug")."""
    n, e = report["nodes"], report["edges"]

    def gt_name(gid: str) -> str:
        obj = gt.by_id.get(gid) if gt is not None else None
        return f"{gid} {obj.category}" if obj is not None else gid

    def nm(node_id: str, fallback: str = "") -> str:
        return names.get(node_id, fallback or node_id)

    out = [
        ("Matched nodes", ["object", "GT", "distance m"],
         [[nm(p["node"], p["label"]), p["gt"], f"{p['distance']:.2f}"] for p in n["pairs"]]),
        ("Duplicate nodes", ["object", "repeats GT", "distance m"],
         [[nm(p["node"], p["label"]), p["gt"], f"{p['distance']:.2f}"] for p in n["duplicates"]]),
        ("Spurious nodes", ["object", "nearest GT", "distance m"],
         [[nm(p["node"], p["label"]), p.get("nearest_gt", ""),
           f"{p['nearest_distance']:.2f}" if "nearest_distance" in p else ""] for p in n["spurious"]]),
        ("Missing GT objects", ["GT", "category", "sure"],
         [[g["gt"], g["coco"], "yes" if g["sure"] else "no"] for g in n["missing"]]),
        ("Edges by type", ["type", "GT checked", "found", "graph (judged)", "correct"],
         [[t, str(c["gt"]), str(c["found"]), str(c["graph"]), str(c["correct"])] for t, c in e["per_type"].items()]),
        ("Spurious edges (between matched nodes)", ["subject", "relation", "object"],
         [[nm(s), t, nm(o)] for s, t, o in e["spurious"]]),
        ("Missed GT relations (checked)", ["subject", "relation", "object"],
         [[gt_name(s), t, gt_name(o)] for s, t, o in e["missed"]]),
    ]
    vqa = report.get("vqa")
    if vqa is not None:
        out.append(("VQA (sure questions)", ["status", "question", "expected", "answer"],
                    [[q["status"], q["question"], str(q["expected"]),
                      str(q.get("answer", q.get("got", q.get("reason", ""))))] for q in vqa["questions"]]))
    return out


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def write_report(out_dir: Path, report: dict, scene: Scene, gt, room: str, *, width: int = 1600,
                 height: int = 1200) -> list[Path]:
    """Write DIR/graph.png, DIR/report.md, DIR/report.html; returns their paths. `scene`: the
    room from sg3d.app.scene.fetch_scene."""
    from sg3d.render.diagram import render_diagram

    out_dir.mkdir(parents=True, exist_ok=True)
    png = render_diagram(scene, "png", size=(width, height), status=node_status(report),
                         markers=missing_markers(report, gt, room), title=f"eval {report['room']}")
    (out_dir / PICTURE).write_bytes(png)
    rows = metric_rows(report)
    names = {n.id: n.name or "" for n in scene.nodes}     # the names ask, plan and the picture use
    parts = tables(report, names, gt)

    md = [f"# sg3d eval: {report['room']}", "",
          f"Match tolerance {report['tolerance_m']} m.", "",
          "| metric | value |", "|---|---:|"]
    md += [f"| {k} | {v} |" for k, v in rows]
    md += ["", f"![graph: matched green, spurious red, duplicate orange, missing GT hollow]({PICTURE})", "",
           "Top-down view on a metre grid: each node at its object's floor position; "
           "green = matched a GT object, red = spurious, orange = duplicate of a matched object, "
           "hollow red rings = GT objects the graph lacks, at their annotated position.", ""]
    for title, header, body in parts:
        md += [f"## {title} ({len(body)})", ""]
        if body:
            md += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            md += ["| " + " | ".join(_md_cell(c) for c in r) + " |" for r in body]
        md.append("")
    (out_dir / "report.md").write_text("\n".join(md), encoding="utf-8")

    esc = html.escape
    img = base64.b64encode(png).decode()
    page = ["<!DOCTYPE html>", '<html><head><meta charset="utf-8">',
            f"<title>sg3d eval {esc(report['room'])}</title>",
            "<style>body{font:14px sans-serif;margin:2em}table{border-collapse:collapse;margin-bottom:1em}"
            "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}td.v{text-align:right}"
            "img{max-width:100%}</style>",
            "</head><body>", f"<h1>sg3d eval: {esc(report['room'])}</h1>",
            f"<p>Match tolerance {report['tolerance_m']} m.</p>",
            "<table><tr><th>metric</th><th>value</th></tr>"]
    page += [f"<tr><td>{esc(k)}</td><td class=\"v\">{esc(v)}</td></tr>" for k, v in rows]
    page += ["</table>",
             f'<p><img alt="scene graph coloured by evaluation status" src="data:image/png;base64,{img}"></p>',
             "<p>Green: matched; red: spurious; orange: duplicate; hollow red ring: missing GT object.</p>"]
    for title, header, body in parts:
        page.append(f"<h2>{esc(title)} ({len(body)})</h2>")
        if body:
            page.append("<table><tr>" + "".join(f"<th>{esc(h)}</th>" for h in header) + "</tr>")
            page += ["<tr>" + "".join(f"<td>{esc(str(c))}</td>" for c in r) + "</tr>" for r in body]
            page.append("</table>")
    page.append("</body></html>")
    (out_dir / "report.html").write_text("\n".join(page), encoding="utf-8")
    return [out_dir / PICTURE, out_dir / "report.md", out_dir / "report.html"]
