"""A built generated room against its exact ground truth, with the matching `sg3d eval` uses
(`sg3d.evaluation.matching`: one to one, Hungarian, within a distance) and its edge judge.

Per layout: the floor verdict (a floor node at the true floor's height where the frames saw the
floor, none where they did not), whether the top of the focus desk or table (the shelf's top
board in a shelf sweep) is held by an object node (`top_is_an_object`), any-label
recall and precision over the seen objects taller than FLAT_MAX_M and recall over the flat ones
(1-5 cm), ON precision and recall against the exact supports, and the median relative size error
of matched objects (horizontal extents sorted, so a box's turn in the plane does not count)."""
from __future__ import annotations

from dataclasses import replace
from typing import Optional

import numpy as np

from benchmarks.synth.truth import FLAT_MAX_M

# The generator's positions are exact box centres: a node must lie this near (or within half
# its own size, `matching.reach`) to stand for an object, and its largest extent must be within
# SIZE_RATIO of the object's (a desk-wide node does not stand for a phone on the desk).
TOLERANCE_M = 0.3
SIZE_RATIO = 3.0
FLOOR_HEIGHT_TOL_M = 0.08
TOP_HEIGHT_TOL_M = 0.05


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


WALL_PLANE_TOL_M = 0.15


def wall_verdict(gt: dict, nodes) -> tuple[int, int]:
    """(seen walls that a wall node lies on, wall nodes that lie on no wall): a node lies on a
    wall when its centre is within WALL_PLANE_TOL_M of the wall's plane (x = 0, x = W, y = 0,
    y = D in the room frame) and it runs along it (longer along the plane than across)."""
    W, D = gt["room"]["size"][:2]
    T = np.asarray(gt["room_to_world"])
    planes = {"wall-west": (0, 0.0), "wall-east": (0, W), "wall-south": (1, 0.0), "wall-north": (1, D)}
    seen = {w["id"] for w in gt["structure"]["walls"] if w["seen"]}
    hit, wrong = set(), 0
    for n in (n for n in nodes if n.layer == "structure" and n.label == "wall"):
        c = T[:3, :3].T @ (np.asarray(n.position, float) - T[:3, 3])
        on = [w for w, (axis, at) in planes.items() if abs(c[axis] - at) <= WALL_PLANE_TOL_M]
        hit |= set(on)
        wrong += not on
    return len(hit & seen), wrong


def match_objects(objects, gt, info: dict):
    """`sg3d.evaluation.matching` (Hungarian over feasible distances) with sizes that agree."""
    from scipy.optimize import linear_sum_assignment

    from sg3d.evaluation.matching import Matching, feasible_distances

    located = [g for g in gt.objects if g.position is not None]
    d = feasible_distances(objects, located, TOLERANCE_M, lambda a, b: True)
    for i, n in enumerate(objects):
        for j, g in enumerate(located):
            if n.size and not 1 / SIZE_RATIO <= max(n.size) / max(info[g.id]["size"]) <= SIZE_RATIO:
                d[i, j] = np.inf
    pairs = []
    if d.size:
        rows, cols = linear_sum_assignment(np.where(np.isfinite(d), d, 1e9))
        pairs = [(objects[i].id, located[j].id, float(d[i, j])) for i, j in zip(rows, cols) if np.isfinite(d[i, j])]
    matched = {n for n, _, _ in pairs}
    found = {g for _, g, _ in pairs}
    return Matching(pairs, [n.id for n in objects if n.id not in matched], [],
                    [g.id for g in located if g.id not in found])


def top_is_an_object(gt: dict, furniture: dict, objects) -> bool:
    """Some object node is the furniture with its top: the node's upper face lies at the top's
    height (within TOP_HEIGHT_TOL_M: a segment of the desk and the wall behind it is not its
    top), the top's centre within half its larger horizontal extent, and it is at least half as
    long as the top."""
    lo, hi = (np.asarray(furniture["box_gravity"][k]) for k in ("min", "max"))
    T = np.asarray(gt["room_to_world"])
    centre = np.r_[(lo[:2] + hi[:2]) / 2, hi[2]]
    for n in objects:
        if not n.size:
            continue
        c = T[:3, :3].T @ (np.asarray(n.box_centre or n.position, float) - T[:3, 3])
        half_h, reach = n.size[2] / 2, max(n.size[:2]) / 2
        if (abs(c[2] + half_h - centre[2]) <= TOP_HEIGHT_TOL_M
                and np.linalg.norm(c[:2] - centre[:2]) <= reach and max(n.size[:2]) >= 0.5 * max(hi[:2] - lo[:2])):
            return True
    return False


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

    gt = parse_gt(gt_dict, coco_names=set())
    gt = replace(gt, objects=[replace(g, coco=g.category) for g in gt.objects])
    info = {o["id"]: o for o in gt_dict["objects"]}
    objects = [n for n in nodes if n.layer != "structure"]
    m = match_objects(objects, gt, info)
    seen = [o for o in gt_dict["objects"] if o["seen"]]
    tall = [o for o in seen if o["size"][2] > FLAT_MAX_M]
    flat = [o for o in seen if o["size"][2] <= FLAT_MAX_M]
    ok_floor, floor_said = floor_verdict(gt_dict, nodes)
    walls_found, walls_wrong = wall_verdict(gt_dict, nodes)
    by_node = {n.id: n for n in objects}
    errors = [e for n, g, _ in m.pairs if (e := _size_error(by_node[n].size, info[g]["size"])) is not None]
    on = edge_metrics([r for r in gt.relations if r.type == "ON"], [e for e in edges if e["type"] == "ON"], m)
    focus = gt_dict["room"].get("focus")
    return {
        "kind": gt_dict["kind"], "seed": gt_dict["seed"],
        "floor_seen": gt_dict["structure"]["floor"]["seen"], "floor_said": floor_said, "floor_right": ok_floor,
        "walls_seen": sum(w["seen"] for w in gt_dict["structure"]["walls"]), "walls_found": walls_found,
        "walls_wrong": walls_wrong,
        "focus_object": top_is_an_object(gt_dict, info[focus], objects) if focus and info[focus]["seen"] else None,
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
    head = ("kind", "layouts", "floor right", "walls found (wrong)", "focus top an object", "any R (>= 5 cm)", "any P",
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
            kind, str(len(rs)), floor,
            f"{sum(r.get('walls_found', 0) for r in rs)}/{sum(r.get('walls_seen', 0) for r in rs)}"
            f" ({sum(r.get('walls_wrong', 0) for r in rs)})",
            f"{sum(focus)}/{len(focus)}" if focus else "-",
            _r(s["tall_found"], s["tall"]), _r(s["matched"], s["nodes"]), _r(s["flat_found"], s["flat"]),
            _r(s["on_correct"], s["on_graph"]), _r(s["on_found"], s["on_gt"]),
            f"{np.median(errs):.2f}" if errs else "-")))
    return "\n".join(lines)
