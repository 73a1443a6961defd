"""The merge's decisions, without a store (paper Sec. V-C): from a local graph and the stored
candidates it was compared with, which local object is which stored node, which stored nodes
fold into one, which unmatched observation is a moved node, the properties every node gets, the
tally changes and the relation rows. `sg3d.graphdb.merge` reads the inputs inside the merge
transaction and writes the plan with `apply`.

Same-node detection is Eq. 10-15: s_total = w_label s_label (Eq. 10-11) + w_colour s_colour
(Eq. 14) + w_position s_position (Eq. 12-13), paired one-to-one; a matched node is updated with
the paper's rules (`sg3d.merge.update`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable, Optional, TypeVar

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import linear_sum_assignment

from sg3d.core.embedding import LabelEmbedding
from sg3d.core.geometry import (
    DESK_LABEL,
    FLOOR_STANDING_LABELS,
    SOLID_TO_THE_FLOOR,
    carrel_panel,
    gravity_basis,
)
from sg3d.core.model import UNNAMED_LABEL, LocalGraph, ObjectObservation, ScanInfo
from sg3d.core.shape import shape_class
from sg3d.core.stored import Row
from sg3d.merge import rescan
from sg3d.merge.consistency import canonical_rows
from sg3d.merge.histograms import pack_hist, unpack_hist
from sg3d.merge.ids import MergeIds
from sg3d.merge.similarity import (
    SimilarityParams,
    box_may_pass,
    box_position_similarity,
    histogram_intersection,
    label_similarity_matrix,
    position_may_pass,
    position_similarity,
    shared_labels,
    total_similarity,
)
from sg3d.merge.update import (
    combine_boxes,
    combine_gaussians,
    combine_histograms,
    combine_labels,
    incoming_has_best_label,
)

T = TypeVar("T")
Label = tuple[str, Optional[str]]       # (label, colour) of an object entering or leaving the tallies


@dataclass
class MergePlan:
    """Everything one merge writes, decided before the first write of its objects."""
    key: Optional[str]
    room: str
    scan: ScanInfo
    now: float
    frames: list[int]
    candidates: int = 0                                         # stored nodes compared
    node_ids: dict[str, str] = field(default_factory=dict)      # local_id -> global id
    cleared: list[str] = field(default_factory=list)            # moved nodes: their edges go
    folds: list[tuple[str, str]] = field(default_factory=list)  # (stored node, node it folds into)
    updates: list[Row] = field(default_factory=list)           # object_update rows
    creates: list[Row] = field(default_factory=list)           # object_create rows
    counted: list[Label] = field(default_factory=list)          # entering the tallies
    uncounted: list[Label] = field(default_factory=list)        # leaving the tallies
    empty_places: list[Row] = field(default_factory=list)      # object_mark_empty rows
    relations: list[tuple[str, list[Row]]] = field(default_factory=list)  # (type, relation_merge rows)
    resolve: bool = False                                       # the touched pairs need resolving
    claimed: int = 0                                            # unnamed pieces of stored named objects

    @property
    def moved(self) -> int:
        return len(self.cleared)

    @property
    def absorbed(self) -> int:
        return len(self.folds)


def _box_centre(obj: ObjectObservation) -> tuple[float, float, float]:
    return obj.box_centre if obj.box_centre is not None else obj.mean


def _position_arrays(objects: list[ObjectObservation], near: list[Row]) -> dict:
    """Broadcast-ready (n_local, n_cand, 3) operands of the position tests."""
    return {
        "mean_c": np.array([o.mean for o in objects], float)[:, None, :],
        "mean_o": np.array([[c["x"], c["y"], c["z"]] for c in near], float)[None, :, :],
        "var_o": np.array([c["var"] for c in near], float)[None, :, :],
        "size_o": np.array([c["size"] for c in near], float)[None, :, :],
        "box_o": np.array([_stored_centre(c) for c in near], float)[None, :, :],
        "box_c": np.array([_box_centre(o) for o in objects], float)[:, None, :],
        "size_c": np.array([o.size for o in objects], float)[:, None, :],
        # unnamed objects are no kind: two of them are one place only by the plain Gaussian test
        "same_kind": (shared_labels([o.labels for o in objects], [c["labels"] for c in near]) > 0)
        & np.array([o.label != UNNAMED_LABEL for o in objects])[:, None]
        & np.array([c["label"] != UNNAMED_LABEL for c in near])[None, :],
    }


def _wide_floor(a: dict, params: SimilarityParams) -> np.ndarray:
    """σ floor of a stored object between views of one kind: a fraction of its largest extent."""
    return np.maximum(params.sigma_floor, params.sigma_size_fraction * a["size_o"].max(axis=-1))[..., None]


def may_pass(objects: list[ObjectObservation], near: list[Row], params: SimilarityParams,
              basis: np.ndarray) -> np.ndarray:
    """(n_local, n_cand): False only where `position_scores` is surely below the position
    threshold (no normal tails evaluated)."""
    a, p_min = _position_arrays(objects, near), params.min_position_similarity()
    ok = position_may_pass(a["mean_o"], a["var_o"], a["mean_c"], p_min, params.sigma_floor, params.sigma_cap)
    if a["same_kind"].any():
        # σ_wide ≥ σ, so the wide test covers the plain one for same-kind pairs
        wide = position_may_pass(a["mean_o"], a["var_o"], a["mean_c"], p_min, _wide_floor(a, params),
                                 params.sigma_cap)
        box = box_may_pass(a["box_o"], a["size_o"], a["box_c"], a["size_c"], basis, p_min, params.sigma_floor)
        ok = ok | (a["same_kind"] & (wide | box))
    return ok | box_claims(objects, near, basis)


def position_scores(objects: list[ObjectObservation], near: list[Row], params: SimilarityParams,
                     basis: np.ndarray) -> np.ndarray:
    """s_position (Eq. 12-13) of every (local, candidate) pair, shape (n_local, n_cand).

    Partial views of one big object: its σ is floored at a fraction of its extent, and
    overlapping 3-D boxes count as the same place. Only between views of one kind of thing: a
    chair tucked under a table, or a cup on it, sits inside the table's extent and is not it.
    Layers never mix (a shelf's surface is not the book on it), and structure (floors, walls,
    counters: big, thin boxes whose Gaussians say little) is the same place only where the
    boxes overlap (`structure_position_similarity`).
    """
    a = _position_arrays(objects, near)
    s_pos = position_similarity(a["mean_o"], a["var_o"], a["mean_c"], params.sigma_floor, params.sigma_cap)
    s_box = None
    if a["same_kind"].any():
        s_wide = position_similarity(a["mean_o"], a["var_o"], a["mean_c"], _wide_floor(a, params),
                                     params.sigma_cap)
        s_box = box_position_similarity(a["box_o"], a["size_o"], a["box_c"], a["size_c"], basis,
                                        params.sigma_floor)
        s_pos = np.where(a["same_kind"], np.maximum(s_pos, np.maximum(s_wide, s_box)), s_pos)
    s_pos = structure_position_similarity(objects, near, s_pos, s_box, a["same_kind"])
    # a pair a stored box may claim stays a candidate (the claim rules decide after the matching);
    # at the lowest passing score it matches only with perfect label and colour scores
    return np.where(box_claims(objects, near, basis), np.maximum(s_pos, params.min_position_similarity()), s_pos)


def box_claims(objects: list[ObjectObservation], near: list[Row], basis: np.ndarray) -> np.ndarray:
    """(n_local, n_cand): the pairs one of the stored-box rules may join (`claimed_by_stored_box`:
    an unnamed observation and a stored named floor-standing object; `stored_pieces_named`: a named
    floor-standing observation and a stored unnamed object) whose boxes overlap by CLAIM_SHARE of
    the smaller, and the pairs `panel_pairs` finds (a carrel's panel beside a stored desk). Their
    Gaussians may lie far apart (a chair's base seen alone, a chair's whole box, a panel's end), so
    the position test alone would not even make them candidates."""
    unnamed = np.array([o.layer == "object" and o.label == UNNAMED_LABEL for o in objects], bool)
    standing = np.array([o.layer == "object" and o.label in FLOOR_STANDING_LABELS for o in objects], bool)
    stored = np.array([_stored_object(c) for c in near], bool)
    stored_standing = stored & np.array([c["label"] in FLOOR_STANDING_LABELS for c in near], bool)
    stored_unnamed = stored & np.array([c["label"] == UNNAMED_LABEL for c in near], bool)
    pairs = (unnamed[:, None] & stored_standing[None, :]) | (standing[:, None] & stored_unnamed[None, :])
    panels = panel_pairs(objects, near, basis)
    if not pairs.any():
        return panels
    ca = np.array([_box_centre(o) for o in objects], float) @ basis.T
    cb = np.array([_stored_centre(c) for c in near], float) @ basis.T
    ha = np.array([o.size for o in objects], float) / 2
    hb = np.array([c["size"] for c in near], float) / 2
    lo = np.maximum(ca[:, None] - ha[:, None], cb[None] - hb[None])
    hi = np.minimum(ca[:, None] + ha[:, None], cb[None] + hb[None])
    inter = np.prod(np.clip(hi - lo, 0, None), axis=-1)
    smaller = np.maximum(np.minimum.outer(np.prod(2 * ha, axis=1), np.prod(2 * hb, axis=1)), 1e-9)
    return (pairs & (inter / smaller >= CLAIM_SHARE)) | panels


def structure_position_similarity(objects: list[ObjectObservation], near: list[Row], s_pos: np.ndarray,
                                  s_box: Optional[np.ndarray], same_kind: np.ndarray) -> np.ndarray:
    """Rule "layers do not mix": s_position 0 between a structure node and an object; between two
    structure nodes of one kind the box term alone (overlapping boxes), else 0."""
    local = np.array([o.layer == "structure" for o in objects])[:, None]
    stored = np.array([(c.get("layer") or "object") == "structure" for c in near])[None, :]
    out = np.where(local != stored, 0.0, s_pos)
    both = local & stored
    if both.any():
        box = s_box if s_box is not None else np.zeros_like(s_pos)
        out = np.where(both, np.where(same_kind, box, 0.0), out)
    return out


def _pair_scores(objects: list[ObjectObservation], cands: list[Row], s_pos: np.ndarray,
                 embedding: LabelEmbedding, params: SimilarityParams) -> np.ndarray:
    """s_total (Eq. 15) for every (local object, candidate) pair, shape (n_local, n_cand)."""
    n, m = len(objects), len(cands)
    if n == 0 or m == 0:
        return np.zeros((n, m))
    s_col = np.zeros((n, m))
    # only pairs close enough to pass get the 512-bin intersection
    rows, cols = np.nonzero(s_pos >= params.min_position_similarity())
    if rows.size:
        h_c = np.array([o.hist for o in objects], float)
        h_o = np.array([unpack_hist(c["hist"]) for c in cands], float)
        s_col[rows, cols] = histogram_intersection(h_c[rows], h_o[cols])
    s_lab = label_similarity_matrix([o.labels for o in objects], [o.scores for o in objects],
                                    [c["labels"] for c in cands], [c["scores"] for c in cands], embedding)
    return total_similarity(s_lab, s_col, s_pos, params)


def match_nodes(objects: list[ObjectObservation], cands: list[Row], s_pos: np.ndarray,
                embedding: LabelEmbedding, params: SimilarityParams = SimilarityParams()
                ) -> tuple[dict[int, int], dict[int, int]]:
    """Same-node detection: (local index -> candidate index, one-to-one, s_total ≥ threshold;
    candidate index -> the candidate index it is the same node as).

    The second map: when a new observation passes the threshold against several stored nodes
    that nothing else claims, those nodes were one object all along (a table first seen as two
    ends, linked by a view of its middle), so they are folded into the matched one; not for an
    unnamed, structure or shape-named observation, whose label is no evidence that they are one
    thing (a row of desks looks alike from end to end).
    """
    scores = _pair_scores(objects, cands, s_pos, embedding, params)
    if scores.size == 0:
        return {}, {}
    rows, cols = linear_sum_assignment(-scores)
    matches = {int(i): int(j) for i, j in zip(rows, cols) if scores[i, j] >= params.threshold}
    claimed = set(matches.values())
    absorbed: dict[int, int] = {}
    for i, j in matches.items():
        if objects[i].label == UNNAMED_LABEL or objects[i].layer == "structure" or objects[i].named_by == "shape":
            continue        # nothing names what links them: two segments (or walls) stay two
        for k in np.flatnonzero(scores[i] >= params.threshold):
            if int(k) not in claimed and int(k) not in absorbed:
                absorbed[int(k)] = j
    return matches, absorbed


def _as_observation(cand: dict) -> ObjectObservation:
    """A stored node seen as one more observation of another node (for folding it in)."""
    return ObjectObservation(
        local_id=cand["id"], labels=list(cand["labels"]), scores=list(cand["scores"]),
        mean=(cand["x"], cand["y"], cand["z"]), var=tuple(cand["var"]), n_points=int(cand["n_points"]),
        size=tuple(cand["size"]), hist=unpack_hist(cand["hist"]), colour=cand["colour"], thumbnail=None,
        colour2=cand.get("colour2"), layer=cand.get("layer") or "object", shape=cand.get("shape"),
        named_by=cand.get("named_by"), first_frame=int(cand["first_frame"]), last_frame=int(cand["last_frame"]),
        n_frames=int(cand["n_frames"]), box_centre=cand["box_centre"])


def stored_shape(label: str, layer: str, size: Iterable[float], surface: Optional[Iterable[float]], basis: np.ndarray,
                 centre: Optional[Iterable[float]], said: Optional[str]) -> Optional[str]:
    """The `shape` a node stores: for an unnamed object, the shape class of its (merged) box and
    the surface points at hand (`sg3d.core.shape.shape_class`); for any other node the word it
    came with (None: no shape is said of what has a name)."""
    if label != UNNAMED_LABEL or layer != "object":
        return said
    return shape_class(size, surface, basis, centre)


def _new_props(obj: ObjectObservation, oid: str, rid: str, now: float, scan: ScanInfo,
               basis: Optional[np.ndarray] = None) -> dict:
    """The properties of the node `oid` that observation `obj` makes in room `rid`."""
    mean = [float(v) for v in obj.mean]
    size = [float(v) for v in obj.size]
    basis = gravity_basis(None) if basis is None else basis
    return {
        "id": oid, "room": rid,
        "label": obj.label, "labels": list(obj.labels), "scores": [float(s) for s in obj.scores],
        "score": float(max(obj.scores)),
        "x": mean[0], "y": mean[1], "z": mean[2], "var": [float(v) for v in obj.var],
        "n_points": int(obj.n_points), "size": size, "volume": float(np.prod(size)),
        "box_centre": [float(v) for v in _box_centre(obj)],
        "hist": pack_hist(obj.hist), "colour": obj.colour, "colour2": obj.colour2,
        "layer": obj.layer, "named_by": obj.named_by,
        "shape": stored_shape(obj.label, obj.layer, size, obj.surface, basis, _box_centre(obj), obj.shape),
        "surface": None if obj.surface is None else [float(v) for v in obj.surface],
        "thumbnail": obj.thumbnail or b"",
        "first_frame": int(obj.first_frame), "last_frame": int(obj.last_frame),
        "observations": 1, "n_frames": int(obj.n_frames), "updated_at": now,
        **rescan.first_sighting(scan),
    }


def _updated_props(cand: dict, obj: ObjectObservation, now: float, basis: np.ndarray,
                   scan: Optional[ScanInfo] = None) -> dict:
    labels, scores = combine_labels(cand["labels"], cand["scores"], obj.labels, obj.scores)
    mean, var, n = combine_gaussians([cand["x"], cand["y"], cand["z"]], cand["var"], cand["n_points"],
                                     obj.mean, obj.var, obj.n_points)
    hist = combine_histograms(unpack_hist(cand["hist"]), obj.hist)
    centre, size = combine_boxes(_stored_centre(cand), cand["size"],
                             _box_centre(obj), obj.size, basis)
    # a structure node stays structure
    layer = "structure" if "structure" in (cand.get("layer"), obj.layer) else "object"
    props = {
        "label": labels[0], "labels": labels, "scores": scores, "score": float(max(scores)),
        "x": float(mean[0]), "y": float(mean[1]), "z": float(mean[2]), "var": [float(v) for v in var],
        "n_points": int(n), "size": [float(v) for v in size], "volume": float(np.prod(size)),
        "box_centre": [float(v) for v in centre], "hist": pack_hist(hist),
        # the dominant colour follows the larger share of the combined histogram's pixels
        "colour": obj.colour if float(np.sum(obj.hist)) > float(np.sum(hist)) / 2 else cand["colour"],
        "colour2": obj.colour2 if float(np.sum(obj.hist)) > float(np.sum(hist)) / 2 else cand.get("colour2"),
        # an unnamed object's shape follows its merged box (with this view's points)
        "layer": layer,
        "shape": stored_shape(labels[0], layer, size, obj.surface, basis, centre, obj.shape or cand.get("shape")),
        # who named it follows the label the node keeps: the shape, while the shape's name leads
        "named_by": obj.named_by if labels[0] == obj.label else cand.get("named_by"),
        # (null would remove the property: a view without surface points keeps the stored ones)
        **({} if obj.surface is None else {"surface": [float(v) for v in obj.surface]}),
        "first_frame": min(int(cand["first_frame"]), int(obj.first_frame)),
        "last_frame": max(int(cand["last_frame"]), int(obj.last_frame)),
        "observations": int(cand["observations"]) + 1,
        "n_frames": int(cand["n_frames"]) + int(obj.n_frames), "updated_at": now,
    }
    if incoming_has_best_label(cand["scores"], obj.scores) and obj.thumbnail:
        props["thumbnail"] = obj.thumbnail
    if scan is not None:
        props.update(rescan.sighting(cand, scan))
    return props


def _appearance_split(props: dict) -> dict:
    """A write row: the Object's own properties, and the histogram and thumbnail (None = keep
    the stored one) that go to its Appearance node (schema 2)."""
    own = dict(props)
    return {"props": own, "hist": own.pop("hist"), "thumbnail": own.pop("thumbnail", None)}


def plan_merge(graph: LocalGraph, candidates: list[Row], s_pos: Optional[np.ndarray],
               moved_from: list[Row], embedding: LabelEmbedding, scan: ScanInfo, now: float,
               ids: MergeIds, params: SimilarityParams = SimilarityParams()) -> MergePlan:
    """The plan of one merge. `candidates`: the stored nodes near the local graph (with their
    histograms) and `s_pos` their (n_local, n_cand) position similarity (Eq. 12-13);
    `moved_from`: the stored nodes whose place this graph's frames saw empty (rows of
    cypher/rescan_candidates, with histograms); `ids`: the room and its revision in the merge
    transaction, which name the nodes the merge makes (`sg3d.merge.ids`)."""
    room = ids.room
    plan = MergePlan(key=graph.key, room=room, scan=scan, now=now, frames=[int(f) for f in graph.frames],
                     candidates=len(candidates))
    objects, basis = graph.objects, gravity_basis(graph.up)
    matches, absorbed = (match_nodes(objects, candidates, s_pos, embedding, params)
                         if candidates and s_pos is not None else ({}, {}))
    matches.update(stored_pieces_named(objects, candidates, matches, absorbed, basis))
    seen = {candidates[j]["id"] for j in matches.values()} | {candidates[k]["id"] for k in absorbed}
    moved_locals = _plan_moves(plan, graph, matches, seen, moved_from, embedding, basis)
    for i, obj in enumerate(objects):
        if i in moved_locals:
            continue
        if i in matches:
            _plan_update(plan, obj, candidates, matches[i], absorbed, basis)
        elif (owner := (claimed_by_stored_box(obj, candidates, basis)
                        or claimed_by_stored_desk(obj, candidates, basis)
                        or desk_named_solid(obj, candidates, basis))) is not None:
            plan.node_ids[obj.local_id] = owner      # a piece of a stored chair is that chair
            plan.claimed += 1
        else:
            props = _new_props(obj, ids.object_id(i), room, now, scan, basis)
            plan.node_ids[obj.local_id] = props["id"]
            plan.creates.append(_appearance_split(props))
            plan.counted.append((props["label"], props["colour"]))
    plan.empty_places = rescan.empty_place_rows(graph.empty_places, seen)
    # stored form between global ids (symmetric edges by the smaller GLOBAL id, no viewpoint
    # relations); then the pairs this merge touched keep only their better-supported statement
    plan.relations = [(rel_type, [{**r, "at": now} for r in rows])
                      for rel_type, rows in sorted(canonical_rows(graph.relations, plan.node_ids).items())]
    plan.resolve = bool(graph.relations) or plan.absorbed > 0
    return plan


# A stored named floor-standing object's box claims an unnamed observation when this share of the
# observation's box lies inside it (the rule `sg3d.ingest.discover.discovery.named_by` applies
# within one build, across scans).
CLAIM_SHARE = 0.5


def box_inside_share(centre_a: ArrayLike, size_a: ArrayLike, centre_b: ArrayLike, size_b: ArrayLike,
                     basis: np.ndarray) -> float:
    """The share of box A's volume inside box B, both axis-aligned in the gravity frame `basis`."""
    ca, cb = basis @ np.asarray(centre_a, float), basis @ np.asarray(centre_b, float)
    ha, hb = np.asarray(size_a, float) / 2, np.asarray(size_b, float) / 2
    overlap = np.clip(np.minimum(ca + ha, cb + hb) - np.maximum(ca - ha, cb - hb), 0, None)
    return float(np.prod(overlap) / max(float(np.prod(2 * ha)), 1e-9))


def box_overlap_share(centre_a: ArrayLike, size_a: ArrayLike, centre_b: ArrayLike, size_b: ArrayLike,
                      basis: np.ndarray) -> float:
    """The share of the smaller of two boxes inside the other (`box_inside_share` both ways)."""
    return max(box_inside_share(centre_a, size_a, centre_b, size_b, basis),
               box_inside_share(centre_b, size_b, centre_a, size_a, basis))


def _stored_centre(cand: Row) -> list[float]:
    """A stored node's box centre (its Gaussian mean where no box was stored)."""
    return cand["box_centre"] or [cand["x"], cand["y"], cand["z"]]


def _stored_object(cand: dict) -> bool:
    return (cand.get("layer") or "object") == "object"


def _most_inside(shares: Iterable[tuple[T, float]]) -> Optional[T]:
    """The key with the largest share of at least CLAIM_SHARE (the last of equal shares), else None."""
    best, best_share = None, CLAIM_SHARE
    for key, share in shares:
        if share >= best_share:
            best, best_share = key, share
    return best


def claimed_by_stored_box(obj: ObjectObservation, candidates: list[Row], basis: np.ndarray) -> Optional[str]:
    """Rule "stored named boxes claim": an unnamed observation with CLAIM_SHARE of its box inside
    the box of a stored named floor-standing object (a chair, a desk) is a piece of it seen
    again (a chair's base the second scan did not name); returns that node's id, else None."""
    if obj.label != UNNAMED_LABEL or obj.layer != "object":
        return None
    return _most_inside((c["id"], box_inside_share(_box_centre(obj), obj.size, _stored_centre(c), c["size"], basis))
                        for c in candidates if c["label"] in FLOOR_STANDING_LABELS and _stored_object(c))


def _gravity_box(centre: ArrayLike, size: ArrayLike, basis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    c, half = basis @ np.asarray(centre, float), np.asarray(size, float) / 2
    return c - half, c + half


def _panel_of(obj: ObjectObservation, cand: dict, basis: np.ndarray) -> bool:
    """Whether an unnamed observation is a carrel panel (`sg3d.core.geometry.carrel_panel`) of a
    stored desk."""
    return (obj.label == UNNAMED_LABEL and obj.layer == "object" and cand["label"] == DESK_LABEL
            and _stored_object(cand)
            and carrel_panel(*_gravity_box(_box_centre(obj), obj.size, basis),
                             *_gravity_box(_stored_centre(cand), cand["size"], basis)))


def panel_pairs(objects: list[ObjectObservation], near: list[Row], basis: np.ndarray) -> np.ndarray:
    """(n_local, n_cand): the (unnamed observation, stored desk) pairs where the observation is a
    panel of that desk's carrel (`_panel_of`)."""
    out = np.zeros((len(objects), len(near)), bool)
    desks = [j for j, c in enumerate(near) if c["label"] == DESK_LABEL]
    for i, obj in enumerate(objects):
        if obj.label == UNNAMED_LABEL:
            for j in desks:
                out[i, j] = _panel_of(obj, near[j], basis)
    return out


def claimed_by_stored_desk(obj: ObjectObservation, candidates: list[Row], basis: np.ndarray) -> Optional[str]:
    """Rule "a carrel's panel", across scans: an unnamed observation that is a carrel panel
    (`sg3d.core.geometry.carrel_panel`: thin, beside a desk, rising above its top) of a STORED
    desk is part of that desk (a later scan that never saw the desk tops sees only the panels);
    returns the nearest such desk's id (box centres in the gravity frame), else None."""
    desks = [c for c in candidates if _panel_of(obj, c, basis)]
    if not desks:
        return None
    centre = basis @ np.asarray(_box_centre(obj), float)
    return min(desks, key=lambda c: float(np.linalg.norm(basis @ np.asarray(_stored_centre(c), float) - centre)))["id"]


def _solid_over_desk(obj: ObjectObservation, cand: dict, basis: np.ndarray) -> bool:
    return (obj.layer == "object" and obj.label in SOLID_TO_THE_FLOOR and cand["label"] == DESK_LABEL
            and cand.get("named_by") == "shape" and _stored_object(cand)
            and box_inside_share(_stored_centre(cand), cand["size"], _box_centre(obj), obj.size, basis) >= CLAIM_SHARE)


def desk_named_solid(obj: ObjectObservation, candidates: list[Row], basis: np.ndarray) -> Optional[str]:
    """Rule "the shape decides": a detection of a kind solid to the floor (SOLID_TO_THE_FLOOR: a
    refrigerator, an oven) whose box holds CLAIM_SHARE of a stored desk named from its shape (a top
    with knee space: the floor seen under it) is that desk misread (a carrel's panel and its desk
    read as a refrigerator); returns the desk's id (the one most inside), else None. Judged
    against the candidates the position test found (a stored desk there is one: the new scan's
    own view of it, or its panels, lie close), so the pair takes no part in the matching."""
    return _most_inside((c["id"], box_inside_share(_stored_centre(c), c["size"], _box_centre(obj), obj.size, basis))
                        for c in candidates if _solid_over_desk(obj, c, basis))


def stored_pieces_named(objects: list[ObjectObservation], candidates: list[Row], matches: dict[int, int],
                        absorbed: dict[int, int], basis: np.ndarray) -> dict[int, int]:
    """Rule "a named box claims the stored piece it overlaps": a named floor-standing observation
    that matched no node updates the stored unnamed node whose box and its own overlap by
    CLAIM_SHARE of the smaller (`box_overlap_share`: a chair an earlier scan saw only as its base,
    or as a blob with its base spread wider than the chair's box); local index -> candidate."""
    taken = set(matches.values()) | set(absorbed)
    out: dict[int, int] = {}
    for i, obj in enumerate(objects):
        if i in matches or obj.label not in FLOOR_STANDING_LABELS or obj.layer != "object":
            continue
        best = _most_inside((j, box_overlap_share(_stored_centre(c), c["size"], _box_centre(obj), obj.size, basis))
                            for j, c in enumerate(candidates)
                            if j not in taken and c["label"] == UNNAMED_LABEL and _stored_object(c))
        if best is not None:
            out[i] = best
            taken.add(best)
    return out


def _plan_moves(plan: MergePlan, graph: LocalGraph, matches: dict[int, int], seen: set[str],
                moved_from: list[Row], embedding: LabelEmbedding, basis: np.ndarray) -> set[int]:
    """Rule "moved" (`sg3d.merge.rescan.is_move`) for the observations that matched no node: each
    move updates the stored node in place; returns the local indices that moved a node."""
    objects = graph.objects
    unmatched = [i for i in range(len(objects)) if i not in matches]
    old = [o for o in moved_from if o["id"] not in seen]
    moves = rescan.pair_moves([objects[i] for i in unmatched], old, embedding) if unmatched else {}
    for n, node in moves.items():
        obj = objects[unmatched[n]]
        plan.node_ids[obj.local_id] = node["id"]
        props = rescan.moved_props(node, _updated_props(node, obj, plan.now, basis, plan.scan), obj, plan.scan)
        plan.cleared.append(node["id"])
        plan.updates.append({"id": node["id"], **_appearance_split(props)})
        plan.uncounted.append((node["label"], node["colour"]))
        plan.counted.append((props["label"], props["colour"]))
        seen.add(node["id"])
    return {unmatched[n] for n in moves}


def _plan_update(plan: MergePlan, obj: ObjectObservation, candidates: list[Row], j: int,
                 absorbed: dict[int, int], basis: np.ndarray) -> None:
    """A matched observation updates its node (the paper's update rules), folding in the stored
    nodes it showed to be the same object."""
    cand = candidates[j]
    plan.node_ids[obj.local_id] = cand["id"]
    props = _updated_props(cand, obj, plan.now, basis, plan.scan)
    for k in (k for k, into in absorbed.items() if into == j):
        other = candidates[k]
        folded = _updated_props({**cand, **props}, _as_observation(other), plan.now, basis, plan.scan)
        folded["observations"] = props["observations"] + int(other["observations"])
        props = folded
        plan.folds.append((other["id"], cand["id"]))
        if other.get("removed_at") is None:
            plan.uncounted.append((other["label"], other["colour"]))
    plan.updates.append({"id": cand["id"], **_appearance_split(props)})
    if cand.get("removed_at") is None:     # a removed node seen again comes back
        plan.uncounted.append((cand["label"], cand["colour"]))
    plan.counted.append((props["label"], props["colour"]))
