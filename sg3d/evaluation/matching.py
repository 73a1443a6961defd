"""One-to-one matching of graph nodes to ground-truth objects (`sg3d eval`).

A node may stand for a GT object when their categories agree (same COCO class, or synonyms by
the taxonomy) and the node lies within a distance tolerance of the annotated position. Among
the feasible pairs the assignment with least total distance is taken (Hungarian method), so a
node can never be counted for two objects nor an object for two nodes.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from sg3d.evaluation.ground_truth import GTObject

# Annotated positions are rough (the annotator's estimate of an object's centre, in a tilted
# world frame, from depth that is not registered to colour), and a node's position is the mean
# of the points seen of it, which moves with the part that was seen. 0.5 m keeps a chair from
# matching its neighbour (chairs around a table stand ~0.8 m apart) while forgiving both errors.
DEFAULT_TOLERANCE = 0.5
# A big object's mean can be far from the annotated point (half a table seen): a node may also
# match while the GT point lies within half its own largest extent, up to this cap.
MAX_EXTENT_ALLOWANCE = 1.5
_INFEASIBLE = 1e9


@dataclass(frozen=True)
class Node:
    id: str
    label: str
    position: tuple[float, float, float]
    size: Optional[tuple[float, float, float]] = None
    colour: Optional[str] = None
    layer: str = "object"
    box_centre: Optional[tuple[float, float, float]] = None     # its box's centre (position: its Gaussian's mean)


@dataclass
class Matching:
    pairs: list[tuple[str, str, float]]          # (node id, GT id, distance m)
    spurious: list[str]                          # unmatched nodes that are not duplicates
    duplicates: list[tuple[str, str, float]]     # (node id, GT id it repeats, distance)
    missing: list[str]                           # located GT objects with a COCO class, unmatched
    node_to_gt: dict[str, str] = field(default_factory=dict)
    gt_to_node: dict[str, str] = field(default_factory=dict)

    def __post_init__(self):
        self.node_to_gt = {n: g for n, g, _ in self.pairs}
        self.gt_to_node = {g: n for n, g, _ in self.pairs}


def reach(node: Node, tolerance: float) -> float:
    """How far from a node a GT point may lie and still be the same object."""
    if not node.size:
        return tolerance
    return max(tolerance, min(MAX_EXTENT_ALLOWANCE, 0.5 * max(node.size)))


def feasible_distances(nodes: Sequence[Node], objects: Sequence[GTObject], tolerance: float,
                       same_category: Callable[[str, str], bool]) -> np.ndarray:
    """Distance matrix (nodes x GT objects) with infeasible pairs set to +inf."""
    d = np.full((len(nodes), len(objects)), np.inf)
    for j, g in enumerate(objects):
        if g.coco is None or g.position is None:
            continue
        gp = np.asarray(g.position, float)
        for i, n in enumerate(nodes):
            if not same_category(n.label, g.coco):
                continue
            dist = float(np.linalg.norm(np.asarray(n.position, float) - gp))
            if dist <= reach(n, tolerance):
                d[i, j] = dist
    return d


def match(nodes: Sequence[Node], objects: Sequence[GTObject], tolerance: float = DEFAULT_TOLERANCE,
          same_category: Optional[Callable[[str, str], bool]] = None) -> Matching:
    """Hungarian assignment of nodes to located, COCO-categorised GT objects."""
    same = same_category or (lambda a, b: a.strip().lower() == b.strip().lower())
    d = feasible_distances(nodes, objects, tolerance, same)
    pairs: list[tuple[str, str, float]] = []
    if d.size:
        cost = np.where(np.isfinite(d), d, _INFEASIBLE)
        rows, cols = linear_sum_assignment(cost)
        pairs = [(nodes[i].id, objects[j].id, float(d[i, j])) for i, j in zip(rows, cols) if np.isfinite(d[i, j])]
    matched_nodes = {n for n, _, _ in pairs}
    matched_gt = {g for _, g, _ in pairs}
    duplicates, spurious = [], []
    for i, n in enumerate(nodes):
        if n.id in matched_nodes:
            continue
        # a second node for an object that already has one: the merge failed to fuse them
        near = [(float(d[i, j]), objects[j].id) for j in range(len(objects))
                if np.isfinite(d[i, j]) and objects[j].id in matched_gt]
        if near:
            dist, gid = min(near)
            duplicates.append((n.id, gid, dist))
        else:
            spurious.append(n.id)
    missing = [g.id for g in objects if g.coco is not None and g.position is not None and g.id not in matched_gt]
    return Matching(pairs, spurious, duplicates, missing)
