"""A built generated room against its exact ground truth, with the matching `sg3d eval` uses
(`sg3d.evaluation.matching`: one to one, Hungarian, within a distance) and its edge judge.

Per layout: the floor verdict (a floor node at the true floor's height where the frames saw the
floor, none where they did not), whether the focus desk or table is an object node, any-label
recall and precision over the seen objects taller than FLAT_MAX_M and recall over the flat ones
(1-5 cm), ON precision and recall against the exact supports, and the median relative size error
of matched objects (horizontal extents sorted, so a box's turn in the plane does not count)."""
from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from benchmarks.synth.truth import FLAT_MAX_M

# The generator's positions are exact box centres: a node must lie this near (or within half
# its own size, `matching.reach`) to stand for an object.
TOLERANCE_M = 0.3
FLOOR_HEIGHT_TOL_M = 0.08


def _height(gt: dict, p) -> float:
    T = np.asarray(gt["room_to_world"])
    return float((T[:3, :3].T @ (np.asarray(p, float) - T[:3, 3]))[2])


def floor_verdict(gt: dict, nodes) -> tuple[bool, str]:
    """(right, what the build said): "floor at h m", "not seen"."""
    floors = [n for n in nodes if n.layer == "structure" and n.label == "floor"]
    seen = gt["structure"]["floor"]["seen"]
    if not floors:
        return (not seen), "not seen"
    h = _height(gt, floors[0].position)
    return (seen and abs(h) <= FLOOR_HEIGHT_TOL_M), f"floor at {h:+.2f} m"


def _size_error(node_size, gt_size) -> Optional[float]:
    if not node_size:
        return None
    n = sorted(node_size[:2]) + [node_size[2]]
    g = sorted(gt_size[:2]) + [gt_size[2]]
    return float(np.mean([abs(a - b) / b for a, b in zip(n, g)]))


def judge(gt_dict: dict, nodes, edges) -> dict:
    """`nodes`: `sg3d.evaluation.matching.Node`s of the room (structure included); `edges`: rows
    with s, type, o."""
    from sg3d.evaluation.edges import edge_metrics
    from sg3d.evaluation.ground_truth import parse_gt
    from sg3d.evaluation.matching import match

    gt = parse_gt(gt_dict, coco_names=set())
    gt = replace(gt, objects=[replace(g, coco=g.category) for g in gt.objects])
    info = {o["id"]: o for o in gt_dict["objects"]}
    objects = [n for n in nodes if n.layer != "structure"]
    m = match(objects, [g for g in gt.objects if g.position is not None], TOLERANCE_M, lambda a, b: True)
    seen = [o for o in gt_dict["objects"] if o["seen"]]
    tall = [o for o in seen if o["size"][2] > FLAT_MAX_M]
    flat = [o for o in seen if o["size"][2] <= FLAT_MAX_M]
    ok_floor, floor_said = floor_verdict(gt_dict, nodes)
    by_node = {n.id: n for n in objects}
    errors = [e for n, g, _ in m.pairs if (e := _size_error(by_node[n].size, info[g]["size"])) is not None]
    on = edge_metrics([r for r in gt.relations if r.type == "ON"], [e for e in edges if e["type"] == "ON"], m)
    focus = gt_dict["room"].get("focus")
    return {
        "kind": gt_dict["kind"], "seed": gt_dict["seed"],
        "floor_seen": gt_dict["structure"]["floor"]["seen"], "floor_said": floor_said, "floor_right": ok_floor,
        "focus_object": (focus in m.gt_to_node) if focus and info[focus]["seen"] else None,
        "tall": len(tall), "tall_found": sum(o["id"] in m.gt_to_node for o in tall),
        "flat": len(flat), "flat_found": sum(o["id"] in m.gt_to_node for o in flat),
        "nodes": len(objects), "matched": len(m.pairs),
        "on_gt": on["checked"], "on_found": on["found"], "on_graph": on["judged"], "on_correct": on["correct"],
        "on_all": len(gt.relations),
        "size_errors": [round(e, 3) for e in errors],
        "missing": sorted(f"{info[g]['category']}" for g in info if info[g]["seen"] and g not in m.gt_to_node),
    }


def _r(a: int, b: int) -> str:
    return "-" if not b else f"{a / b:.2f}"


def table(rows: list[dict]) -> str:
    """One line per kind: micro-averaged over its layouts."""
    head = ("kind", "layouts", "floor right", "focus furniture an object", "any R (>= 5 cm)", "any P",
            "flat R (1-5 cm)", "ON P", "ON R", "median size error")
    lines = [" | ".join(head), " | ".join("---" for _ in head)]
    for kind in dict.fromkeys(r["kind"] for r in rows):
        rs = [r for r in rows if r["kind"] == kind]
        s = {k: sum(r[k] for r in rs) for k in ("tall", "tall_found", "flat", "flat_found", "nodes", "matched",
                                               "on_gt", "on_found", "on_graph", "on_correct")}
        focus = [r["focus_object"] for r in rs if r["focus_object"] is not None]
        not_seen = sum(not r["floor_seen"] for r in rs)
        floor = f"{sum(r['floor_right'] for r in rs)}/{len(rs)}" + (f" ({not_seen} not seen)" if not_seen else "")
        errs = [e for r in rs for e in r["size_errors"]]
        lines.append(" | ".join((
            kind, str(len(rs)), floor, f"{sum(focus)}/{len(focus)}" if focus else "-",
            _r(s["tall_found"], s["tall"]), _r(s["matched"], s["nodes"]), _r(s["flat_found"], s["flat"]),
            _r(s["on_correct"], s["on_graph"]), _r(s["on_found"], s["on_gt"]),
            f"{np.median(errs):.2f}" if errs else "-")))
    return "\n".join(lines)
