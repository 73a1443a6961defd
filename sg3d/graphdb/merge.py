"""Merging a local 3-D scene graph into the stored global graph (paper Sec. V-C).

The whole merge of one local graph is ONE write transaction (`session.execute_write`, retried
on transient errors): a failure anywhere inside, in Python or in Cypher, rolls everything back.
Inside it: lock the room, read the candidates (same room, inside a spatial window around the
local graph) and the nodes a re-scan saw gone, plan the merge without the store
(`sg3d.merge.plan`: scores, one-to-one pairing, folds, moves, properties, tally changes), then
`apply` the plan: update the matched nodes, create the rest (each Object with its Appearance
node: histogram and thumbnail), adjust the room's tallies (`sg3d.graphdb.tally`), merge the edges,
and log the merge under the graph's key so that a re-run or `--resume` skips it.

Re-scans (the rules `sg3d.merge.rescan`, their reads and writes `sg3d.graphdb.rescan`): every merge
belongs to a scan; nodes keep first/last seen and the scans that saw them. A new observation that matches no node but matches by label and colour a
node whose place this scan saw empty moves that node (history kept). The scan's last merge
marks removed the nodes whose place it saw empty and that it did not re-observe.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Optional, TypeVar, cast

import numpy as np
from neo4j import ManagedTransaction, Result

from sg3d.core.embedding import LabelEmbedding, default_embedding
from sg3d.core.geometry import gravity_basis
from sg3d.core.model import RELATION_TYPES, LocalGraph, ObjectObservation
from sg3d.core.stored import Row
from sg3d.graphdb import cypher, rescan
from sg3d.graphdb.protocol import GraphStore
from sg3d.graphdb.consistency import resolve_pairs
from sg3d.graphdb.store import size_batches
from sg3d.graphdb.tally import create_objects_and_tallies
from sg3d.graphdb.values import room_id
from sg3d.merge.plan import (
    MergePlan,
    may_pass,
    plan_merge,
    position_scores,
)
from sg3d.merge.ids import MergeIds
from sg3d.merge.rescan import scan_of
from sg3d.merge.similarity import MAX_EXTENT_M, SimilarityParams

# A writer's check, run first in each of its transactions (`sg3d.graphdb.lease.RoomLease.fence`).
Fence = Callable[[ManagedTransaction], None]

_R = TypeVar("_R")


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


def _rows(result: Result) -> list[Row]:
    """Records as plain dicts (cheaper than Result.data(), which re-walks every value)."""
    keys = result.keys()
    return [dict(zip(keys, values)) for values in result.values()]


def _fetch_candidates(tx: ManagedTransaction, rid: str, objects: list[ObjectObservation],
                      params: SimilarityParams, basis: np.ndarray) -> tuple[list[Row], np.ndarray]:
    """Candidates and the (n_local, n_cand) position similarity (Eq. 12-13) of each pair.

    One query for the candidates inside the window (small Object records, no bytes); the
    histograms of the ones some local object is close to come from their Appearance nodes.
    """
    largest = max(max(o.size) for o in objects)
    margin = params.window_margin() + (min(largest, MAX_EXTENT_M) + MAX_EXTENT_M) / 2
    near = _rows(tx.run(cypher.load("merge_candidates"), room=rid, **_window(objects, margin)))
    if not near:
        return [], np.zeros((len(objects), 0))
    # in the order of their place, not of their ids: equal scores are then paired the same way
    # in every build of the same frames, whatever the room held before
    near.sort(key=lambda c: (c["x"], c["y"], c["z"], c["label"]))
    # a batch spans the room, so most pairs are far apart: a cheap test drops the candidates
    # nothing local can reach before the exact scores (same result, without their tails)
    near = [near[j] for j in np.flatnonzero(may_pass(objects, near, params, basis).any(axis=0))]
    if not near:
        return [], np.zeros((len(objects), 0))
    s_pos = position_scores(objects, near, params, basis)
    keep = np.flatnonzero((s_pos >= params.min_position_similarity()).any(axis=0))
    if keep.size == 0:
        return [], np.zeros((len(objects), 0))
    cands = [near[j] for j in keep]
    hists = {r["id"]: r["hist"] for r in _rows(tx.run(cypher.load("merge_candidate_hists"),
                                                      ids=[c["id"] for c in cands]))}
    for c in cands:
        c["hist"] = hists.get(c["id"])
    return cands, s_pos[:, keep]


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
                params: SimilarityParams = SimilarityParams(), fence: Optional[Fence] = None) -> MergeReport:
    """The body of the merge transaction (`merge_local_graph` runs it with execute_write): check
    the writer still holds the room (`fence`, `sg3d.graphdb.lease.RoomLease.fence`), lock the
    room, read what the plan needs, plan the merge (`plan_merge`), write it (`apply`)."""
    t0 = time.perf_counter()
    if fence is not None:
        fence(tx)
    if graph.key and tx.run(cypher.load("merge_log_exists"), key=graph.key).single():
        return MergeReport(key=graph.key, skipped=True)
    embedding = embedding or default_embedding()
    rid = room_id(graph.building, graph.room)
    now = time.time()
    ids = lock_room(tx, graph)
    scan = scan_of(graph, now, ids)
    tx.run(cypher.load("scan_ensure"), id=scan.id, room=rid, at=scan.at,
           kind="ingest" if (graph.key or "").startswith("ingest:") else "build").consume()
    objects = graph.objects
    cands, s_pos = (_fetch_candidates(tx, rid, objects, params, gravity_basis(graph.up)) if objects
                    else ([], None))
    moved_from = rescan.move_candidates(tx, rid, graph)
    plan = plan_merge(graph, cands, s_pos, moved_from, embedding, scan, now, ids, params)
    report = apply(tx, plan)
    report.seconds = time.perf_counter() - t0
    return report


def lock_room(tx: ManagedTransaction, graph: LocalGraph) -> MergeIds:
    """The first write of a merge or publish transaction: the room (and its building) made if new,
    locked, its revision bumped (cypher/room_ensure); the ids of the nodes this transaction makes
    follow from the room and that revision (`sg3d.merge.ids`)."""
    rid = room_id(graph.building, graph.room)
    row = tx.run(cypher.load("room_ensure"), building=graph.building, room=rid, name=graph.room,
                 up=[float(v) for v in graph.up] if graph.up is not None else None).single()
    return MergeIds(rid, int(row["revision"]) if row is not None else 0)


def apply(tx: ManagedTransaction, plan: MergePlan) -> MergeReport:
    """Write a merge plan: the templates only, in the order the room's state needs (moved nodes
    lose their stale edges and folded nodes go before the updates; the scan closes before the
    creates, so new objects are not the scan's to remove and the removed ones leave the tallies
    written with the creates)."""
    report = MergeReport(key=plan.key, candidates=plan.candidates, moved=plan.moved, absorbed=plan.absorbed,
                         node_ids=dict(plan.node_ids))
    for node in plan.cleared:
        rescan.clear_relations(tx, node)
    for old, into in plan.folds:
        _fold_node(tx, old, into)
    # rows go in batches under the store's message bound (`size_batches`): thumbnails and
    # histograms of thousands of objects would not fit in one Bolt message
    for rows in size_batches(plan.updates):
        tx.run(cypher.load("object_update"), rows=rows).consume()
    report.updated, report.created = len(plan.updates) - plan.moved, len(plan.creates)
    rescan.record_empty_places(tx, plan.scan, plan.empty_places)
    uncounted = list(plan.uncounted)
    if plan.scan.closes:
        gone = rescan.close_scan(tx, plan.room, plan.scan, plan.now)
        uncounted.extend((g["label"], g["colour"]) for g in gone)
        report.removed = len(gone)
    groups = size_batches(plan.creates) or [[]]
    for group in groups[:-1]:
        create_objects_and_tallies(tx, plan.room, group, ())
    create_objects_and_tallies(tx, plan.room, groups[-1], plan.counted, uncounted)   # the tallies with the last
    for rel_type, rows in plan.relations:
        for batch in size_batches(rows):
            tx.run(cypher.render("relation_merge", rel_type), rows=batch).consume()
        report.relations += len(rows)
    if plan.resolve:
        resolve_pairs(tx, plan.node_ids.values())
    if plan.key:
        tx.run(cypher.load("merge_log_create"), key=plan.key, room=plan.room, at=plan.now,
               frames=plan.frames, created=report.created, updated=report.updated).consume()
    return report


def merge_local_graph(store: GraphStore, graph: LocalGraph, embedding: Optional[LabelEmbedding] = None,
                      params: SimilarityParams = SimilarityParams(), fence: Optional[Fence] = None,
                      room_in_tx: bool = False) -> MergeReport:
    """Merge one local graph as ONE transaction; the store is unchanged if anything fails.
    `room_in_tx`: a new room is created by the merge transaction itself (room_ensure), not in a
    transaction of its own before it, so a merge that fails leaves no room behind (an ingest).
    A merge that loses a race with another writer of the room runs again (`write_room`)."""
    embedding = embedding or default_embedding()
    store.ensure_schema()
    if not room_in_tx:
        ensure_room(store, graph.building, graph.room)
    return write_room(store, lambda tx: merge_in_tx(tx, graph, embedding, params, fence), graph.key)


# A room's writers race at most a few at once (a build, a map, an ingest): more losses in a row
# than this mean the constraint is not a race
ROOM_WRITE_ATTEMPTS = 5


def write_room(store: GraphStore, work: Callable[[ManagedTransaction], _R], key: Optional[str] = None) -> _R:
    """Rule "a room write that loses a race is retried": run `work` (a merge or publish, which
    locks the room first, `lock_room`) as one write transaction. On an optimistic store
    (ArcadeDB) two writers of one room both read its revision before either commits, so both
    name their new nodes alike (`sg3d.merge.ids`) and the loser's commit fails on the unique id,
    or on the unique room two writers created: a ConstraintError, not the retryable conflict
    the driver retries. The loser runs again and reads the winner's revision. A loser with the
    winner's merge `key` is the same local graph: the winner's commit is its merge (skipped)."""
    from neo4j.exceptions import ConstraintError

    for attempt in range(ROOM_WRITE_ATTEMPTS):
        try:
            return store.execute_write(work)
        except ConstraintError:
            if key and store.read("merge_log_exists", key=key):
                return cast(_R, MergeReport(key=key, skipped=True))
            if attempt == ROOM_WRITE_ATTEMPTS - 1:
                raise
            time.sleep(0.02 * (attempt + 1))
    raise AssertionError("unreachable")


def ensure_room(store: GraphStore, building: str, room: str) -> None:
    """The room exists (`create_room`); created once per store handle: later writes skip the round trip."""
    rid = room_id(building, room)
    if rid not in store.rooms_known:
        create_room(store, building, room)
        store.rooms_known.add(rid)


def create_room(store: GraphStore, building: str, room: str, attempts: int = 4) -> None:
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


def merged_keys(store: GraphStore, prefix: str) -> set[str]:
    """Keys of the merges logged under `prefix` (what a resumed build may skip)."""
    return {row["key"] for row in store.read("merge_log_keys", prefix=prefix)}
