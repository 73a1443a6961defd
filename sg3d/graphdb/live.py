"""Publishing a live map's graph (`sg3d map`): the room's graph replaced by the current one, as
a diff with stable node ids, in ONE transaction.

A live map holds the whole room's evidence and recomputes its local graph from it (fusion,
existence, discovery, relations: `sg3d.ingest.live`), so each publish is not a merge of new
evidence into old nodes (that is `sg3d.graphdb.merge`, for builds and re-scans) but the room's
current answer. The diff keeps what readers hold on to: an object that is still there keeps its
id (`stable_ids`: same label and layer, nearest place), gains its new attributes and evidence;
a new one is created; one that evidence no longer supports is removed, so a rejected
hypothesis never lingers as a duplicate. The properties are those a build's merge gives a new
node (`sg3d.merge.plan.plan_merge` on an empty room), so the last publish is the graph `sg3d build`
makes of the same frames. The room lock (cypher/room_ensure) serialises publishes with every
other writer of the room; readers see the last committed publish and never wait for one.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Optional

import numpy as np
from neo4j import ManagedTransaction

from sg3d.core.embedding import LabelEmbedding, default_embedding
from sg3d.core.model import RELATION_TYPES, LocalGraph, ScanInfo
from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.consistency import resolve_pairs
from sg3d.graphdb.merge import Fence, ensure_room, lock_room, write_room
from sg3d.graphdb.protocol import GraphStore
from sg3d.graphdb.store import size_batches
from sg3d.graphdb.tally import create_objects_and_tallies
from sg3d.graphdb.values import room_id
from sg3d.merge.consistency import canonical_rows
from sg3d.merge.plan import MergePlan, plan_merge

# An object of the new graph keeps a published node's id when it has the node's label and layer
# and lies within this distance of it: farther than a fused object's centre moves while evidence
# gathers (a few centimetres to a couple of decimetres as more of it is seen), nearer than two
# objects of one label usually stand (two chairs side by side are ~0.5 m apart).
STABLE_ID_RADIUS_M = 0.4


@dataclass
class PublishReport:
    created: int = 0
    kept: int = 0          # published nodes that kept their id (attributes and evidence updated)
    removed: int = 0       # published nodes no longer supported by the evidence
    relations: int = 0
    objects: int = 0
    seconds: float = 0.0
    committed_at: float = 0.0   # wall clock (time.time) when the transaction committed


def stable_ids(new: list[Row], old: list[Row], radius: float = STABLE_ID_RADIUS_M) -> dict[int, str]:
    """Index in `new` -> the id of the `old` node it continues: pairs of one label and layer
    within `radius` metres, nearest first, each node used once (a greedy one-to-one matching;
    ties go to the earlier row, so the same inputs always give the same ids)."""
    pairs = []
    for i, n in enumerate(new):
        p = np.array([n["x"], n["y"], n["z"]], float)
        for j, o in enumerate(old):
            if o["label"] != n["label"] or (o.get("layer") or "object") != (n.get("layer") or "object"):
                continue
            d = float(np.linalg.norm(p - np.array([o["x"], o["y"], o["z"]], float)))
            if d <= radius:
                pairs.append((d, i, j))
    out: dict[int, str] = {}
    used: set[int] = set()
    for d, i, j in sorted(pairs):
        if i in out or j in used:
            continue
        out[i] = old[j]["id"]
        used.add(j)
    return out


def resumed_ids(new: list[Row], old: list[Row], unseen: frozenset,
                radius: float = STABLE_ID_RADIUS_M) -> dict[int, str]:
    """`stable_ids` for a resumed map: rule "a resumed map takes back the killed map's ids first".
    The rows are matched to the nodes the killed map published (`unseen`: ids) before any other,
    so a node this run created while it had seen only part of a thing never takes the place of
    the one the killed map published there; the rows left are matched to the other nodes. With
    no `unseen` it is `stable_ids`."""
    first = stable_ids(new, [o for o in old if o["id"] in unseen], radius)
    rest = [i for i in range(len(new)) if i not in first]
    second = stable_ids([new[i] for i in rest], [o for o in old if o["id"] not in unseen], radius)
    return {**first, **{rest[k]: gid for k, gid in second.items()}}


# Objects a live map created carry a first scan named so (`sg3d.app.mapping`: map:<room>@<start>).
MAP_SCAN_PREFIX = "map:"


def made_by_map(row: dict) -> bool:
    """Rule "a publish removes only what a map made": an object is the map's when a map's scan
    created it; a build's or an ingest's object in the room is never the map's to remove."""
    return str(row.get("first_scan") or "").startswith(MAP_SCAN_PREFIX)


def publish_in_tx(tx: ManagedTransaction, graph: LocalGraph, scan: ScanInfo, status: dict,
                  embedding: LabelEmbedding, fence: Optional[Fence] = None,
                  unseen: frozenset = frozenset()) -> PublishReport:
    """The body of one publish (`publish` runs it as one write transaction): check the writer
    still holds the room (`fence`), lock the room, read what maps published there, plan the
    graph's nodes as a build would create them, keep the ids of the nodes that continue
    (`stable_ids`), then write: updates, creates, removals of the map's own nodes no longer
    supported (never of a build's or ingest's, nor of `unseen`: nodes a resumed map has not had the
    chance to see again), the room's tallies recounted, its relations rewritten, its status."""
    t0 = time.perf_counter()
    if fence is not None:
        fence(tx)
    rid = room_id(graph.building, graph.room)
    now = time.time()
    ids = lock_room(tx, graph)
    tx.run(cypher.load("scan_ensure"), id=scan.id, room=rid, at=scan.at, kind="map").consume()
    rows = [dict(r) for r in tx.run(cypher.load("live_objects"), room=rid)]
    old = [o for o in rows if made_by_map(o)]
    plan = plan_merge(graph, [], None, [], embedding, scan, now, ids)
    keep = resumed_ids([row["props"] for row in plan.creates], old, unseen)
    updates, creates = _split_plan(plan, keep, {o["id"]: o.get("first_seen") for o in old})
    kept_ids = set(keep.values())
    gone = [o["id"] for o in old if o["id"] not in kept_ids and o["id"] not in unseen]
    # what stays without being in this graph still counts: a build's objects, the unseen ones
    staying = [(o["label"], o["colour"]) for o in rows if not o["removed"] and o["id"] not in kept_ids
               and (not made_by_map(o) or o["id"] in unseen)]
    for rel_type in RELATION_TYPES:
        tx.run(cypher.render("live_relations_clear", rel_type), room=rid, ids=[o["id"] for o in old]).consume()
    for gid in gone:
        tx.run(cypher.load("node_delete"), id=gid).consume()
    for batch in size_batches(updates):
        tx.run(cypher.load("object_update"), rows=batch).consume()
    # the tallies are recounted: every label and colour of the room as published, and what stays
    tx.run(cypher.load("room_delete_tallies"), room=rid).consume()
    groups = size_batches(creates) or [[]]
    for group in groups[:-1]:
        create_objects_and_tallies(tx, rid, group, ())
    create_objects_and_tallies(tx, rid, groups[-1], list(plan.counted) + staying)   # every node, kept ones too
    n_rel = 0
    for rel_type, rel_rows in sorted(canonical_rows(graph.relations, plan.node_ids).items()):
        for batch in size_batches([{**r, "at": now} for r in rel_rows]):
            tx.run(cypher.render("relation_merge", rel_type), rows=batch).consume()
        n_rel += len(rel_rows)
    if graph.relations:
        resolve_pairs(tx, plan.node_ids.values())
    tx.run(cypher.load("live_status"), room=rid, state=status.get("state", "live"), since=status.get("since"),
           frames=int(status.get("frames", 0)), updated=now, source=status.get("source")).consume()
    return PublishReport(created=len(creates), kept=len(updates), removed=len(gone), relations=n_rel,
                         objects=len(plan.creates), seconds=time.perf_counter() - t0)


def _split_plan(plan: MergePlan, keep: dict[int, str], first_seen: dict) -> tuple[list[Row], list[Row]]:
    """The plan's node rows as updates of the published nodes they continue (`keep`: row index ->
    id; the plan's node ids follow) and creates of the rest."""
    local_of = {gid: lid for lid, gid in plan.node_ids.items()}
    updates, creates = [], []
    for k, row in enumerate(plan.creates):
        if k not in keep:
            creates.append(row)
            continue
        gid = keep[k]
        props = {key: v for key, v in row["props"].items() if key not in ("id", "first_seen", "first_scan", "room")}
        if first_seen.get(gid) is None:
            props["first_seen"] = row["props"]["first_seen"]
        plan.node_ids[local_of[row["props"]["id"]]] = gid
        updates.append({"id": gid, "props": props, "hist": row["hist"], "thumbnail": row["thumbnail"]})
    return updates, creates


def publish(store: GraphStore, graph: LocalGraph, scan: ScanInfo, status: dict,
            embedding: Optional[LabelEmbedding] = None, fence: Optional[Fence] = None,
            unseen: frozenset = frozenset()) -> PublishReport:
    """Replace the map's part of the room's graph by `graph` as ONE transaction (`publish_in_tx`);
    the store is unchanged if anything fails, and readers see the previous publish until this one
    commits."""
    embedding = embedding or default_embedding()
    store.ensure_schema()
    ensure_room(store, graph.building, graph.room)
    report = write_room(store, lambda tx: publish_in_tx(tx, graph, scan, status, embedding, fence, unseen))
    report.committed_at = time.time()
    return report


def map_object_ids(store: GraphStore, building: str, room: str) -> frozenset:
    """The ids of the objects maps made in the room (what a resumed map has yet to see again)."""
    return frozenset(o["id"] for o in store.read("live_objects", room=room_id(building, room)) if made_by_map(o))


def mapping_status(store: GraphStore, building: str, room: str) -> Optional[dict]:
    """The room's live-mapping state (None: the room was never mapped live, or does not exist)."""
    rows = store.read("live_status_get", room=room_id(building, room))
    if not rows or rows[0].get("mapping") is None:
        return None
    return dict(rows[0])
