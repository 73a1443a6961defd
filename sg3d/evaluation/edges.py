"""Edge precision/recall of a scene graph against ground-truth relations (`sg3d eval`).

A GT relation (subject, predicate, object) can be checked only when both ends were matched to
nodes and the predicate has one of our relation types; it is found when the graph has that edge
between the two nodes, read also backwards for symmetric types (NEXT_TO) and as the inverse type
(a ABOVE b = b BELOW a). The GT lists only what annotators judged worth saying, and never
comparatives like BIGGER_THAN, so precision is measured only over graph edges between matched
nodes whose type the GT uses at all: a lower bound, since an unlisted true edge counts as wrong.
GT relations that depend on where the annotator stood (in front of, behind, left of, right of)
are not checked: the graph stores only viewpoint-invariant relations (they are answered at
query time from a stated viewpoint), so they are listed under unmapped["viewpoint"].
"""
from __future__ import annotations

from collections import defaultdict
from typing import Iterable

from sg3d.core.relation_rules import VIEWPOINT
from sg3d.evaluation.ground_truth import INVERSE, SYMMETRIC, GTRelation
from sg3d.evaluation.matching import Matching


def equivalent_edges(s: str, type_: str, o: str) -> set[tuple[str, str, str]]:
    """Every (s, type, o) triple that states the same fact."""
    out = {(s, type_, o)}
    if type_ in SYMMETRIC:
        out.add((o, type_, s))
    if type_ in INVERSE:
        out.add((o, INVERSE[type_], s))
    return out


def edge_metrics(relations: Iterable[GTRelation], edges: Iterable[dict], matching: Matching) -> dict:
    """`edges`: rows with s, type, o (node ids). Returns counts, precision/recall, per type."""
    relations = list(relations)
    graph = {(e["s"], e["type"], e["o"]) for e in edges}
    unmapped: dict[str, list[GTRelation]] = {"unknown_predicate": [], "viewpoint": [], "end_not_matched": []}
    checked: list[tuple[GTRelation, tuple[str, str, str]]] = []
    for r in relations:
        if r.type is None:
            unmapped["unknown_predicate"].append(r)
        elif r.type in VIEWPOINT:
            unmapped["viewpoint"].append(r)
        elif r.subject not in matching.gt_to_node or r.object not in matching.gt_to_node:
            unmapped["end_not_matched"].append(r)
        else:
            checked.append((r, (matching.gt_to_node[r.subject], r.type, matching.gt_to_node[r.object])))

    per_type: dict[str, dict] = defaultdict(lambda: {"gt": 0, "found": 0, "graph": 0, "correct": 0})
    found, missed, truth = [], [], set()
    for r, (s, rtype, o) in checked:
        same = equivalent_edges(s, rtype, o)
        truth |= same
        per_type[rtype]["gt"] += 1
        if same & graph:
            per_type[rtype]["found"] += 1
            found.append(r)
        else:
            missed.append(r)

    gt_types = {r.type for r in relations if r.type}
    for t in INVERSE:                      # an inverse edge type says something the GT could list
        if t in gt_types:
            gt_types.add(INVERSE[t])
    matched = set(matching.node_to_gt)
    judged = [e for e in graph if e[0] in matched and e[2] in matched and e[1] in gt_types]
    correct = [e for e in judged if e in truth]
    for e in judged:
        per_type[e[1]]["graph"] += 1
        if e in truth:
            per_type[e[1]]["correct"] += 1
    wrong = sorted(set(judged) - set(correct))
    on_unmatched = sorted(e for e in graph if e[0] not in matched or e[2] not in matched)
    n_checked = len(checked)
    return {
        "gt_relations": len(relations),
        "checked": n_checked,
        "found": len(found),
        "missed": [_rel(r) for r in missed],
        "unmapped": {k: [_rel(r) for r in v] for k, v in unmapped.items()},
        "recall": (len(found) / n_checked) if n_checked else None,
        # over all GT relations, an unmatched end counts as a miss (the paper's missing edges)
        "recall_all": (len(found) / len(relations)) if relations else None,
        "graph_edges": len(graph),
        "judged": len(judged),
        "correct": len(correct),
        "precision": (len(correct) / len(judged)) if judged else None,
        "spurious": [list(e) for e in wrong],
        "edges_on_unmatched_nodes": len(on_unmatched),
        "per_type": {k: dict(v) for k, v in sorted(per_type.items())},
    }


def _rel(r: GTRelation) -> list[str]:
    return [r.subject, r.predicate, r.object]
