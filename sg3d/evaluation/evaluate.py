"""`sg3d eval`: a stored scene graph against hand-annotated ground truth.

Report: node precision/recall with spurious, missing and duplicate nodes (`sg3d.evaluation.matching`), colour
agreement of matched nodes (`colour_agreement`), edge
precision/recall (`sg3d.evaluation.edges`), VQA accuracy (`sg3d.evaluation.vqa`). GT objects a COCO detector cannot name,
or that carry no position, are listed apart instead of as misses; recall is given both over every
COCO object and over those the annotator counted as `sure`.
"""
from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Callable, Optional

from sg3d.core.model import RELATION_TYPES, UNNAMED_LABEL
from sg3d.evaluation.edges import edge_metrics
from sg3d.evaluation.ground_truth import GroundTruth
from sg3d.evaluation.matching import DEFAULT_TOLERANCE, Matching, Node, match
from sg3d.evaluation.vqa import vqa_metrics

if TYPE_CHECKING:
    from sg3d.graphdb.protocol import GraphStore


def category_matcher() -> Callable[[str, str], bool]:
    """Node label vs GT COCO class: equal, or the label is a word of the one vocabulary of `ask`
    and planning (`sg3d.queries.lexicon`: synonyms.json + taxonomy) that means exactly that class
    (an imported node labelled "mug" is a cup; "glass", meaning a wine glass or a cup, is neither)."""
    from sg3d.queries.lexicon import known

    def norm(s: str) -> str:
        return " ".join(s.strip().lower().split())

    def same(label: str, coco: str) -> bool:
        a, b = norm(label or ""), norm(coco)
        if a == b:
            return True
        target = known(a) if a else None
        return target is not None and target.labels == [b]

    return same


def read_nodes(store: GraphStore, room_id: str) -> list[Node]:
    nodes = []
    for r in store.read("eval_objects", room=room_id):
        if r["x"] is None:
            continue
        size = tuple(r["size"]) if r.get("size") else None
        box = tuple(r["box_centre"]) if r.get("box_centre") else None
        nodes.append(Node(r["id"], r["label"] or "", (r["x"], r["y"], r["z"]), size, r.get("colour"),
                          r.get("layer") or "object", box))
    return nodes


def _ratio(a: int, b: int) -> Optional[float]:
    return a / b if b else None


def node_metrics(gt: GroundTruth, nodes: list[Node], m: Matching) -> dict:
    located = [g for g in gt.objects if g.coco is not None and g.position is not None]
    sure = [g for g in located if g.sure]
    sure_found = sum(g.id in m.gt_to_node for g in sure)
    unsure = [g for g in located if not g.sure]
    label = {n.id: n.label for n in nodes}
    by_node = {n.id: n for n in nodes}
    return {
        "graph_nodes": len(nodes),
        "gt_objects": len(gt.objects),
        "gt_detectable": len(located),
        "matched": len(m.pairs),
        "precision": _ratio(len(m.pairs), len(nodes)),
        "recall": _ratio(len(m.pairs), len(located)),
        "recall_sure": _ratio(sure_found, len(sure)),
        "gt_sure": len(sure),
        "gt_unsure": len(unsure),
        "unsure_found": sum(g.id in m.gt_to_node for g in unsure),
        "pairs": [{"node": n, "gt": g, "label": label[n], "distance": round(d, 3)} for n, g, d in m.pairs],
        "spurious": [{"node": n, "label": label[n], **_nearest_same_category(by_node[n], gt)} for n in m.spurious],
        "duplicates": [{"node": n, "gt": g, "label": label[n], "distance": round(d, 3)} for n, g, d in m.duplicates],
        "missing": [_gt_row(gt.by_id[g]) for g in m.missing],
        "not_detectable": [_gt_row(g) for g in gt.objects if g.coco is None],
        "unlocated": [_gt_row(g) for g in gt.objects if g.coco is not None and g.position is None],
        "hedged_category": [g.id for g in gt.objects if g.coco_hedged],
        "colour": colour_agreement(gt, by_node, m),
    }


def colour_agreement(gt: GroundTruth, by_node: dict, m: Matching) -> dict:
    """Matched nodes whose GT object carries a colour: how many the node's colour names the same
    (`agree` of `with_colour`), and each pair with both colours."""
    rows = []
    for n, g, _ in m.pairs:
        want = gt.by_id[g].colour
        if want:
            got = by_node[n].colour
            rows.append({"node": n, "gt": g, "colour": got, "gt_colour": want,
                         "agree": (got or "").strip().lower() == want.strip().lower()})
    agree = sum(r["agree"] for r in rows)
    return {"agree": agree, "with_colour": len(rows), "agreement": _ratio(agree, len(rows)), "pairs": rows}


def _nearest_same_category(node: Node, gt: GroundTruth) -> dict:
    """Why a node is spurious: the nearest GT object of its own label, if any (a large distance
    says "no such object", a small one says the tolerance or the annotated position is off)."""
    best = None
    for g in gt.objects:
        if g.coco is None or g.position is None or g.coco != (node.label or "").strip().lower():
            continue
        d = sum((a - b) ** 2 for a, b in zip(node.position, g.position)) ** 0.5
        if best is None or d < best[0]:
            best = (d, g.id)
    return {"nearest_gt": best[1], "nearest_distance": round(best[0], 3)} if best else {}


def _gt_row(g) -> dict:
    return {"gt": g.id, "category": g.category, "coco": g.coco, "sure": g.sure}


# Furniture whose box height says whether whole-object boxes work (a table from the floor to
# its top, a chair from the floor to its back).
FURNITURE = ("dining table", "chair", "couch", "bed", "bench", "desk")


def object_metrics(gt: GroundTruth, nodes: list[Node], tolerance: float) -> dict:
    """Every object, named or not: object-layer nodes of ANY label matched one to one to ALL
    located GT objects (whatever their category) within the tolerance."""
    objects = [n for n in nodes if n.layer != "structure"]
    located = [replace(g, coco=g.coco or g.category or g.id) for g in gt.objects if g.position is not None]
    m = match(objects, located, tolerance, lambda a, b: True)
    return {
        "nodes": len(objects),
        "unnamed_nodes": sum(n.label == UNNAMED_LABEL for n in objects),
        "gt_located": len(located),
        "matched": len(m.pairs),
        "recall": _ratio(len(m.pairs), len(located)),
        "precision": _ratio(len(m.pairs), len(objects)),
        "duplicates": len(m.duplicates),
        "spurious": len(m.spurious),
        "missing": [_gt_row(gt.by_id[g]) for g in (g.id for g in located) if g not in m.gt_to_node],
    }


def structure_metrics(nodes: list[Node], named: list[Node], m: Matching) -> dict:
    """The room's structure found (floor, walls, windows, surfaces) and the box heights of matched furniture."""
    structure = [n for n in nodes if n.layer == "structure"]
    furniture = [{"node": n.id, "gt": m.node_to_gt[n.id], "label": n.label, "height_m": round(float(n.size[2]), 3)}
                 for n in named if n.id in m.node_to_gt and n.label in FURNITURE and n.size]
    return {
        "floor": any(n.label == "floor" for n in structure),
        "walls": sum(n.label == "wall" for n in structure),
        "windows": sum(n.label == "window" for n in structure),
        "surfaces": sorted(n.label for n in structure if n.label not in ("floor", "wall", "window")),
        "furniture_heights": furniture,
    }


def evaluate(store: GraphStore, gt: GroundTruth, room_id: str, *, room: str, building: str,
             tolerance: float = DEFAULT_TOLERANCE, answerer: Optional[Callable] = None,
             with_vqa: bool = True) -> dict:
    """The full report as a JSON-ready dict: COCO-named nodes against COCO-named GT objects
    ("nodes", "edges"), every object against every located GT object ("objects"), structure."""
    every = read_nodes(store, room_id)
    nodes = [n for n in every if n.layer != "structure" and n.label != UNNAMED_LABEL]
    m = match(nodes, gt.objects, tolerance, category_matcher())
    edges = store.read("relation_all", room=room_id, types=list(RELATION_TYPES))
    report = {
        "room": room_id,
        "tolerance_m": tolerance,
        "nodes": node_metrics(gt, nodes, m),
        "edges": edge_metrics(gt.relations, edges, m),
        "objects": object_metrics(gt, every, tolerance),
        "structure": structure_metrics(every, nodes, m),
    }
    if with_vqa:
        report["vqa"] = vqa_metrics(store, gt, m, room, building, answerer)
    return report
