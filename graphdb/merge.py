"""Merging a local 3-D scene graph into the stored global graph (paper Sec. V-C).

The whole merge of one local graph is ONE write transaction (`session.execute_write`, retried
on transient errors): a failure anywhere inside, in Python or in Cypher, rolls everything back.
Inside it: fetch candidates (same room, inside a spatial window around the local graph), score
them against the local objects in Python (`graphdb.similarity`), pair them one-to-one, update
the matched nodes, create the rest (each Object with its Appearance node: histogram and
thumbnail), adjust the room's tallies (`graphdb.tally`), merge the edges, and log the merge
under the graph's key so that a re-run or `--resume` skips it.

Re-scans (`graphdb.rescan`): every merge belongs to a scan; nodes keep first/last seen and the
scans that saw them. A new observation that matches no node but matches by label and colour a
node whose place this scan saw empty moves that node (history kept). The scan's last merge
marks removed the nodes whose place it saw empty and that it did not re-observe.
"""
from __future__ import annotations

import time
import uuid
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from neo4j import ManagedTransaction
from scipy.optimize import linear_sum_assignment

from graphdb import cypher
from graphdb.consistency import canonical_rows, resolve_pairs
from graphdb.similarity import (MAX_EXTENT_M, SimilarityParams, box_may_pass,
                                box_position_similarity, histogram_intersection,
                                label_similarity_matrix, position_may_pass, position_similarity,
                                shared_labels, total_similarity)
from graphdb import rescan
from graphdb.tally import create_objects_and_tallies
from graphdb.values import pack_hist, room_id, unpack_hist
from graphdb.update import (combine_boxes, combine_gaussians, combine_histograms, combine_labels,
                            incoming_has_best_label)
from ingest.embedding import LabelEmbedding, default_embedding
from ingest.model import RELATION_TYPES, UNNAMED_LABEL, LocalGraph, ObjectObservation, ScanInfo


@dataclass
class MergeReport:
    key: Optional[str]
    skipped: bool = False          # already merged under this key
    created: int = 0
    updated: int = 0
    candidates: int = 0
    absorbed: int = 0              # stored nodes found to be one object with another, folded in
    relations: int = 0
    moved: int = 0                 # nodes moved to a new place by this merge
    removed: int = 0               # nodes marked removed when this merge closed its scan
    node_ids: dict[str, str] = field(default_factory=dict)   # local_id -> global id
    seconds: float = 0.0


def _rows(result) -> list[dict]:
    """Records as plain dicts (cheaper than Result.data(), which re-walks every value)."""
    keys = result.keys()
    return [dict(zip(keys, values)) for values in result.values()]


def _box_centre(obj: ObjectObservation):
    return obj.box_centre if obj.box_centre is not None else obj.mean


def gravity_basis(up) -> np.ndarray:
    """Rows e1, e2, up of the room's gravity frame (world axes when the room has no up)."""
    if up is None:
        return np.eye(3)
    from ingest.relations import horizontal_basis

    return np.stack(horizontal_basis(up))


def _fetch_candidates(tx: ManagedTransaction, rid: str, objects: list[ObjectObservation],
                      params: SimilarityParams, basis: np.ndarray) -> tuple[list[dict], np.ndarray]:
    """Candidates and the (n_local, n_cand) position similarity (Eq. 12-13) of each pair.

    One query for the candidates inside the window (small Object records, no bytes); the
    histograms of the ones some local object is close to come from their Appearance nodes.
    """
    largest = max(max(o.size) for o in objects)
    margin = params.window_margin() + (min(largest, MAX_EXTENT_M) + MAX_EXTENT_M) / 2
    near = _rows(tx.run(cypher.load("merge_candidates"), room=rid, **_window(objects, margin)))
    if not near:
        return [], np.zeros((len(objects), 0))
    # a batch spans the room, so most pairs are far apart: a cheap test drops the candidates
    # nothing local can reach before the exact scores (same result, without their tails)
    near = [near[j] for j in np.flatnonzero(_may_pass(objects, near, params, basis).any(axis=0))]
    if not near:
        return [], np.zeros((len(objects), 0))
    s_pos = _position_scores(objects, near, params, basis)
    keep = np.flatnonzero((s_pos >= params.min_position_similarity()).any(axis=0))
    if keep.size == 0:
        return [], np.zeros((len(objects), 0))
    cands = [near[j] for j in keep]
    hists = {r["id"]: r["hist"] for r in _rows(tx.run(cypher.load("merge_candidate_hists"),
                                                      ids=[c["id"] for c in cands]))}
    for c in cands:
        c["hist"] = hists.get(c["id"])
    return cands, s_pos[:, keep]


def _position_arrays(objects: list[ObjectObservation], near: list[dict]) -> dict:
    """Broadcast-ready (n_local, n_cand, 3) operands of the position tests."""
    return {
        "mean_c": np.array([o.mean for o in objects], float)[:, None, :],
        "mean_o": np.array([[c["x"], c["y"], c["z"]] for c in near], float)[None, :, :],
        "var_o": np.array([c["var"] for c in near], float)[None, :, :],
        "size_o": np.array([c["size"] for c in near], float)[None, :, :],
        "box_o": np.array([c["box_centre"] or [c["x"], c["y"], c["z"]] for c in near], float)[None, :, :],
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


def _may_pass(objects: list[ObjectObservation], near: list[dict], params: SimilarityParams,
              basis: np.ndarray) -> np.ndarray:
    """(n_local, n_cand): False only where `_position_scores` is surely below the position
    threshold (no normal tails evaluated)."""
    a, p_min = _position_arrays(objects, near), params.min_position_similarity()
    ok = position_may_pass(a["mean_o"], a["var_o"], a["mean_c"], p_min, params.sigma_floor, params.sigma_cap)
    if a["same_kind"].any():
        # σ_wide ≥ σ, so the wide test covers the plain one for same-kind pairs
        wide = position_may_pass(a["mean_o"], a["var_o"], a["mean_c"], p_min, _wide_floor(a, params),
                                 params.sigma_cap)
        box = box_may_pass(a["box_o"], a["size_o"], a["box_c"], a["size_c"], basis, p_min, params.sigma_floor)
        ok = ok | (a["same_kind"] & (wide | box))
    return ok


def _position_scores(objects: list[ObjectObservation], near: list[dict], params: SimilarityParams,
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
    return structure_position_similarity(objects, near, s_pos, s_box, a["same_kind"])


def structure_position_similarity(objects: list[ObjectObservation], near: list[dict], s_pos: np.ndarray,
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


def _pair_scores(objects: list[ObjectObservation], cands: list[dict], s_pos: np.ndarray,
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


def match_nodes(objects: list[ObjectObservation], cands: list[dict], s_pos: np.ndarray,
                embedding: LabelEmbedding, params: SimilarityParams = SimilarityParams()
                ) -> tuple[dict[int, int], dict[int, int]]:
    """Same-node detection: (local index -> candidate index, one-to-one, s_total ≥ threshold;
    candidate index -> the candidate index it is the same node as).

    The second map: when a new observation passes the threshold against several stored nodes
    that nothing else claims, those nodes were one object all along (a table first seen as two
    ends, linked by a view of its middle), so they are folded into the matched one; not for an
    unnamed or structure observation, whose label is no evidence that they are one thing.
    """
    scores = _pair_scores(objects, cands, s_pos, embedding, params)
    if scores.size == 0:
        return {}, {}
    rows, cols = linear_sum_assignment(-scores)
    matches = {int(i): int(j) for i, j in zip(rows, cols) if scores[i, j] >= params.threshold}
    claimed = set(matches.values())
    absorbed: dict[int, int] = {}
    for i, j in matches.items():
        if objects[i].label == UNNAMED_LABEL or objects[i].layer == "structure":
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
        first_frame=int(cand["first_frame"]), last_frame=int(cand["last_frame"]),
        n_frames=int(cand["n_frames"]), box_centre=cand["box_centre"])


def _new_props(obj: ObjectObservation, rid: str, now: float, scan: ScanInfo) -> dict:
    mean = [float(v) for v in obj.mean]
    size = [float(v) for v in obj.size]
    return {
        "id": f"o-{uuid.uuid4().hex[:16]}", "room": rid,
        "label": obj.label, "labels": list(obj.labels), "scores": [float(s) for s in obj.scores],
        "score": float(max(obj.scores)),
        "x": mean[0], "y": mean[1], "z": mean[2], "var": [float(v) for v in obj.var],
        "n_points": int(obj.n_points), "size": size, "volume": float(np.prod(size)),
        "box_centre": [float(v) for v in _box_centre(obj)],
        "hist": pack_hist(obj.hist), "colour": obj.colour, "colour2": obj.colour2,
        "layer": obj.layer, "shape": obj.shape,
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
    centre, size = combine_boxes(cand["box_centre"] or [cand["x"], cand["y"], cand["z"]], cand["size"],
                             _box_centre(obj), obj.size, basis)
    props = {
        "label": labels[0], "labels": labels, "scores": scores, "score": float(max(scores)),
        "x": float(mean[0]), "y": float(mean[1]), "z": float(mean[2]), "var": [float(v) for v in var],
        "n_points": int(n), "size": [float(v) for v in size], "volume": float(np.prod(size)),
        "box_centre": [float(v) for v in centre], "hist": pack_hist(hist),
        # the dominant colour follows the larger share of the combined histogram's pixels
        "colour": obj.colour if float(np.sum(obj.hist)) > float(np.sum(hist)) / 2 else cand["colour"],
        "colour2": obj.colour2 if float(np.sum(obj.hist)) > float(np.sum(hist)) / 2 else cand.get("colour2"),
        # a structure node stays structure; a shape word is kept until a view says another
        "layer": "structure" if "structure" in (cand.get("layer"), obj.layer) else "object",
        "shape": obj.shape or cand.get("shape"),
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


def _window(objects: list[ObjectObservation], margin: float) -> dict:
    means = np.array([o.mean for o in objects], float)
    lo = means.min(axis=0) - margin
    hi = means.max(axis=0) + margin
    return {"xmin": lo[0], "xmax": hi[0], "ymin": lo[1], "ymax": hi[1], "zmin": lo[2], "zmax": hi[2]}


def _fold_node(tx: ManagedTransaction, old: str, into: str) -> None:
    """Move `old`'s relation edges to `into` (counts added, best score kept) and delete it."""
    for rel_type in RELATION_TYPES:
        for name in ("node_fold_out", "node_fold_in"):
            tx.run(cypher.render(name, rel_type), old=old, into=into).consume()
    tx.run(cypher.load("node_delete"), id=old).consume()


def merge_in_tx(tx: ManagedTransaction, graph: LocalGraph, embedding: Optional[LabelEmbedding] = None,
                params: SimilarityParams = SimilarityParams()) -> MergeReport:
    """The body of the merge transaction; `merge_local_graph` runs it with execute_write."""
    t0 = time.perf_counter()
    report = MergeReport(key=graph.key)
    if graph.key and tx.run(cypher.load("merge_log_exists"), key=graph.key).single():
        report.skipped = True
        return report
    embedding = embedding or default_embedding()
    rid = room_id(graph.building, graph.room)
    now = time.time()
    scan = rescan.scan_of(graph, now)
    # first write of the transaction: the room lock (see cypher/room_ensure.cypher)
    tx.run(cypher.load("room_ensure"), building=graph.building, room=rid, name=graph.room,
           up=[float(v) for v in graph.up] if graph.up is not None else None).consume()
    tx.run(cypher.load("scan_ensure"), id=scan.id, room=rid, at=scan.at,
           kind="ingest" if (graph.key or "").startswith("ingest:") else "build").consume()

    objects = graph.objects
    basis = gravity_basis(graph.up)
    cands, s_pos = _fetch_candidates(tx, rid, objects, params, basis) if objects else ([], None)
    report.candidates = len(cands)
    matches, absorbed = match_nodes(objects, cands, s_pos, embedding, params) if cands else ({}, {})

    updates, creates = [], []
    counted, uncounted = [], []     # (label, colour) of objects entering / leaving the tallies
    seen = {cands[j]["id"] for j in matches.values()} | {cands[k]["id"] for k in absorbed}
    unmatched = [i for i in range(len(objects)) if i not in matches]
    moves = rescan.find_moves(tx, rid, graph, [objects[i] for i in unmatched], seen, embedding) if unmatched else {}
    for n, old in moves.items():
        i = unmatched[n]
        obj = objects[i]
        report.node_ids[obj.local_id] = old["id"]
        props = rescan.moved_props(old, _updated_props(old, obj, now, basis, scan), obj, scan)
        rescan.clear_relations(tx, old["id"])
        updates.append({"id": old["id"], **_appearance_split(props)})
        uncounted.append((old["label"], old["colour"]))
        counted.append((props["label"], props["colour"]))
        seen.add(old["id"])
        report.moved += 1
    moved_locals = {unmatched[n] for n in moves}
    for i, obj in enumerate(objects):
        if i in moved_locals:
            continue
        if i in matches:
            cand = cands[matches[i]]
            report.node_ids[obj.local_id] = cand["id"]
            props = _updated_props(cand, obj, now, basis, scan)
            for k in (k for k, j in absorbed.items() if j == matches[i]):
                other = cands[k]
                folded = _updated_props({**cand, **props}, _as_observation(other), now, basis, scan)
                folded["observations"] = props["observations"] + int(other["observations"])
                props = folded
                _fold_node(tx, other["id"], cand["id"])
                if other.get("removed_at") is None:
                    uncounted.append((other["label"], other["colour"]))
                report.absorbed += 1
            updates.append({"id": cand["id"], **_appearance_split(props)})
            if cand.get("removed_at") is None:     # a removed node seen again comes back
                uncounted.append((cand["label"], cand["colour"]))
            counted.append((props["label"], props["colour"]))
        else:
            props = _new_props(obj, rid, now, scan)
            report.node_ids[obj.local_id] = props["id"]
            creates.append(_appearance_split(props))
            counted.append((props["label"], props["colour"]))
    if updates:
        tx.run(cypher.load("object_update"), rows=updates).consume()
    report.updated, report.created = len(updates) - report.moved, len(creates)
    rescan.record_empty_places(tx, scan, graph.empty_places, seen)
    if scan.closes:
        gone = rescan.close_scan(tx, rid, scan, now)
        uncounted.extend((g["label"], g["colour"]) for g in gone)
        report.removed = len(gone)
    # after the scan's close: new objects are not the scan's to remove, and the removed ones
    # leave the tallies written with the creates
    create_objects_and_tallies(tx, rid, creates, counted, uncounted)

    # stored form between global ids (symmetric edges by the smaller GLOBAL id, no viewpoint
    # relations); then the pairs this merge touched keep only their better-supported statement
    for rel_type, rows in sorted(canonical_rows(graph.relations, report.node_ids).items()):
        tx.run(cypher.render("relation_merge", rel_type), rows=[{**r, "at": now} for r in rows]).consume()
        report.relations += len(rows)
    if graph.relations or report.absorbed:
        resolve_pairs(tx, report.node_ids.values())

    if graph.key:
        tx.run(cypher.load("merge_log_create"), key=graph.key, room=rid, at=now,
               frames=[int(f) for f in graph.frames], created=report.created,
               updated=report.updated).consume()
    report.seconds = time.perf_counter() - t0
    return report


def merge_local_graph(store, graph: LocalGraph, embedding: Optional[LabelEmbedding] = None,
                      params: SimilarityParams = SimilarityParams()) -> MergeReport:
    """Merge one local graph as ONE transaction; the store is unchanged if anything fails."""
    embedding = embedding or default_embedding()
    store.ensure_schema()
    rid = room_id(graph.building, graph.room)
    if rid not in store.rooms_known:     # a room is created once: later merges skip the round trip
        create_room(store, graph.building, graph.room)
        store.rooms_known.add(rid)
    from neo4j.exceptions import ConstraintError

    try:
        return store.execute_write(lambda tx: merge_in_tx(tx, graph, embedding, params))
    except ConstraintError:
        # Two merges of one key raced (two runs of one build): the store may report the loser
        # as a duplicate MergeLog key rather than a retryable conflict. The same key means the
        # same local graph, so the winner's commit is this merge.
        if graph.key and store.read("merge_log_exists", key=graph.key):
            return MergeReport(key=graph.key, skipped=True)
        raise


def create_room(store, building: str, room: str, attempts: int = 4) -> None:
    """Create the room before the merge, in its own transaction. Two builds creating one new room
    at once both get here; the one whose commit hits the unique constraint retries and finds it."""
    from neo4j.exceptions import ConstraintError

    for attempt in range(attempts):
        try:
            store.write("room_create", building=building, room=room_id(building, room), room_name=room)
            return
        except ConstraintError:
            if attempt == attempts - 1:
                raise
            time.sleep(0.05 * (attempt + 1))


def merged_keys(store, prefix: str) -> set[str]:
    """Keys of the merges logged under `prefix` (what a resumed build may skip)."""
    return {row["key"] for row in store.read("merge_log_keys", prefix=prefix)}
