"""Re-scans in the store: what the re-scan rules (`sg3d.merge.rescan`) read and what they write.

The nodes a scan saw gone are read inside the merge transaction (`move_candidates`), the plan's
empty places and the scan's close are written there (`record_empty_places`, `close_scan`), and a
re-scan's removal test reads the room's present boxes first (`known_objects`).
"""
from __future__ import annotations

from neo4j import ManagedTransaction

from sg3d.core.model import RELATION_TYPES, KnownObject, LocalGraph, ScanInfo, vec3
from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore
from sg3d.merge.rescan import MIN_EMPTY_FRAMES


def move_candidates(tx: ManagedTransaction, rid: str, graph: LocalGraph) -> list[Row]:
    """The stored nodes whose place this graph's frames saw empty, with their histograms: what
    an unmatched observation may have moved from (`sg3d.merge.rescan.pair_moves`)."""
    ids = sorted(i for i, frames in graph.empty_places.items() if frames)
    if not ids or not graph.objects:
        return []
    rows = tx.run(cypher.load("rescan_candidates"), room=rid, ids=ids)
    old = [dict(zip(rows.keys(), v)) for v in rows.values()]
    if not old:
        return []
    hists = {r["id"]: r["hist"] for r in tx.run(cypher.load("merge_candidate_hists"), ids=[o["id"] for o in old])}
    for o in old:
        o["hist"] = hists.get(o["id"])
    return old


def clear_relations(tx: ManagedTransaction, node_id: str) -> None:
    """A moved node's relation edges described its old place: they go (the new ones follow)."""
    for rel_type in RELATION_TYPES:
        tx.run(cypher.render("object_relations_clear", rel_type), id=node_id).consume()


def record_empty_places(tx: ManagedTransaction, scan: ScanInfo, rows: list[Row]) -> None:
    """Write `sg3d.merge.rescan.empty_place_rows` on their nodes."""
    if rows:
        tx.run(cypher.load("object_mark_empty"), scan=scan.id, rows=rows).consume()


def close_scan(tx: ManagedTransaction, rid: str, scan: ScanInfo, now: float) -> list[Row]:
    """Mark removed the nodes the scan saw gone (see module doc); returns them (id, label, colour)."""
    rows = tx.run(cypher.load("scan_close"), room=rid, scan=scan.id, at=scan.at, min_frames=MIN_EMPTY_FRAMES)
    gone = [dict(zip(rows.keys(), v)) for v in rows.values()]
    tx.run(cypher.load("scan_closed"), id=scan.id, at=now, removed=len(gone)).consume()
    return gone


def known_objects(store: GraphStore, rid: str) -> list[KnownObject]:
    """The room's present objects (boxes) for a re-scan's removal test (`sg3d.ingest.objects.rescan`)."""
    out = []
    for r in store.read("rescan_known", room=rid):
        if not r.get("size") or r.get("x") is None:     # an imported node without a box: not judged
            continue
        centre = r["box_centre"] or [r["x"], r["y"], r["z"]]
        surface = tuple(float(v) for v in r["surface"]) if r.get("surface") else None
        out.append(KnownObject(r["id"], vec3(centre), vec3(r["size"]),
                               surface))
    return out
