"""Re-scans inside the merge transaction: scans, sightings, moved and removed objects.

Every merge belongs to a scan (`sg3d.core.model.ScanInfo`: one `sg3d build` or one `POST /ingest`
batch). In the merge's own transaction (`sg3d.merge.plan` decides with the rules here,
`sg3d.graphdb.merge` and `sg3d.graphdb.rescan` read and write):
- matched and new nodes record the scan (first_seen/last_seen, first_scan/last_scan, scans);
- a new observation that matches no node, but matches by label and colour a node whose place this
  scan saw empty (`is_move`), moves that node: its earlier place goes to its history lists
  (entry k: scan history_scans[k], at history_at[k], moved it from history_x/y/z[k]), its stale
  relation edges go, no duplicate is made;
- the frames that saw a node's place empty (`sg3d.ingest.objects.rescan`) are recorded on the node;
- the scan's last merge closes it: nodes with at least MIN_EMPTY_FRAMES such frames that the scan
  did not re-observe are marked removed (removed_at, removed_scan; the frames stay as evidence)
  and leave the room's tallies. Nothing is deleted; a partial re-scan only judges what it saw.
Since all of it commits with the merge that is logged under its key, a re-run or `--resume`
of a scan changes nothing, and a crash mid-scan leaves the previous state of every chunk.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from sg3d.core.embedding import LabelEmbedding
from sg3d.core.model import LocalGraph, ObjectObservation, ScanInfo
from sg3d.core.stored import Row
from sg3d.merge.histograms import unpack_hist
from sg3d.merge.ids import MergeIds
from sg3d.merge.similarity import histogram_intersection, label_similarity_matrix

# A place seen empty in at least this many frames of a scan (like the existence test's
# "seen twice") is evidence enough to mark an object that the scan did not re-observe removed.
MIN_EMPTY_FRAMES = 2
# A moved object: its label matches (shared top-k labels, or word similarity of the best labels)
# at least MOVE_LABEL_MIN and its colour histograms intersect (Eq. 14) at least MOVE_COLOUR_MIN.
MOVE_LABEL_MIN = 0.7
MOVE_COLOUR_MIN = 0.5
# ... and it keeps its size: each of its extents, largest to smallest, within this factor of the
# stored node's (a box measured from other views, partly hidden, grows or shrinks by up to about
# half; a 20 cm thing is never a 2 m sheet). Extents under MOVE_MIN_EXTENT_M count as that much (a
# flat thing's thickness is depth noise).
MOVE_SIZE_RATIO = 2.0
MOVE_MIN_EXTENT_M = 0.05


def scan_of(graph: LocalGraph, now: float, ids: MergeIds) -> ScanInfo:
    """The scan a local graph belongs to; a graph without one is a scan of its own, named by its
    key, else by the merge (`MergeIds.scan_id`)."""
    if graph.scan is not None:
        return graph.scan
    return ScanInfo(id=graph.key or ids.scan_id(), at=now, closes=True)


def first_sighting(scan: ScanInfo) -> dict:
    """Scan properties of a node this scan creates."""
    return {"first_seen": scan.at, "last_seen": scan.at, "first_scan": scan.id, "last_scan": scan.id,
            "scans": [scan.id]}


def sighting(cand: dict, scan: ScanInfo) -> dict:
    """Scan properties of a stored node this scan re-observes (a removed one comes back)."""
    scans = list(cand.get("scans") or [])
    if scan.id not in scans:
        scans.append(scan.id)
    first = cand.get("first_seen")
    return {"first_seen": scan.at if first is None else first,
            "first_scan": cand.get("first_scan") or scan.id,
            "last_seen": scan.at, "last_scan": scan.id, "scans": scans,
            "removed_at": None, "removed_scan": None}


def is_move(s_label: np.ndarray, s_colour: np.ndarray) -> np.ndarray:
    """Rule "moved": a new observation that matched no node is the same object as a node whose
    place this scan saw empty when s_label >= MOVE_LABEL_MIN (Eq. 10 with unit scores: shared
    top-k labels, else word similarity) and s_colour >= MOVE_COLOUR_MIN (Eq. 14)."""
    return (s_label >= MOVE_LABEL_MIN) & (s_colour >= MOVE_COLOUR_MIN)


def same_size(new_sizes: np.ndarray, old_sizes: np.ndarray) -> np.ndarray:
    """Rule "a move keeps its size": (n, 3) new extents against (m, 3) stored ones -> (n, m) bool,
    true where every extent, sorted largest first and floored at MOVE_MIN_EXTENT_M, is within
    MOVE_SIZE_RATIO of the other's. A stored node without a size passes (nothing to compare)."""
    a = np.sort(np.maximum(np.asarray(new_sizes, float).reshape(-1, 3), MOVE_MIN_EXTENT_M), axis=1)
    b = np.sort(np.maximum(np.asarray(old_sizes, float).reshape(-1, 3), MOVE_MIN_EXTENT_M), axis=1)
    ratio = np.maximum(a[:, None, :] / b[None, :, :], b[None, :, :] / a[:, None, :])
    return (ratio <= MOVE_SIZE_RATIO).all(axis=2)


def pair_moves(objects: list[ObjectObservation], old: list[Row], embedding: LabelEmbedding) -> dict[int, Row]:
    """Index into `objects` (the unmatched new observations) -> the stored node it moved from:
    one-to-one among `old`, the nodes whose place was seen empty and that nothing re-observed
    (`is_move` and `same_size`, best label + colour score first)."""
    if not old or not objects:
        return {}
    s_label = label_similarity_matrix([o.labels for o in objects], [[1.0] * len(o.labels) for o in objects],
                                      [c["labels"] for c in old], [[1.0] * len(c["labels"]) for c in old], embedding)
    h_new = np.array([o.hist for o in objects], float)
    h_old = np.array([unpack_hist(c["hist"]) for c in old], float)
    s_colour = histogram_intersection(h_new[:, None, :], h_old[None, :, :])
    ok = is_move(s_label, s_colour)
    sized = [j for j, c in enumerate(old) if c.get("size") is not None]
    if sized:
        fits = same_size(np.array([o.size for o in objects], float), np.array([old[j]["size"] for j in sized], float))
        ok[:, sized] &= fits
    if not ok.any():
        return {}
    score = np.where(ok, s_label + s_colour, -1.0)
    rows_i, cols_j = linear_sum_assignment(-score)
    return {int(i): old[j] for i, j in zip(rows_i, cols_j) if ok[i, j]}


def moved_props(old: dict, props: dict, obj: ObjectObservation, scan: ScanInfo) -> dict:
    """A moved node's properties: the merged attributes (`props`), but the place of the new
    observation, and the old place appended to its history with the scan that moved it."""
    mean = [float(v) for v in obj.mean]
    size = [float(v) for v in obj.size]
    centre = obj.box_centre if obj.box_centre is not None else obj.mean
    return {**props, "x": mean[0], "y": mean[1], "z": mean[2], "var": [float(v) for v in obj.var],
            "n_points": int(obj.n_points), "size": size, "volume": float(np.prod(size)),
            "box_centre": [float(v) for v in centre],
            "history_scans": list(old.get("history_scans") or []) + [scan.id],
            "history_at": list(old.get("history_at") or []) + [scan.at],
            "history_x": list(old.get("history_x") or []) + [float(old["x"])],
            "history_y": list(old.get("history_y") or []) + [float(old["y"])],
            "history_z": list(old.get("history_z") or []) + [float(old["z"])],
            "moved_scan": scan.id, "moved_at": scan.at}


def empty_place_rows(empty: dict[str, list[int]], seen: set[str]) -> list[Row]:
    """The frames that saw each stored node's place empty, for the nodes this merge did not see
    (cypher/object_mark_empty rows)."""
    return [{"id": i, "frames": sorted({int(f) for f in frames})}
            for i, frames in sorted(empty.items()) if i not in seen and frames]
