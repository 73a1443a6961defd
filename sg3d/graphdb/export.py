"""Reading a room's or a building's scene graph for export (`sg3d.core.stored.StoredGraph`), which
the `formats` package writes as the paper's JSON, GraphML, Spark-DSG or 3DSSG."""
from __future__ import annotations

import base64
from typing import Any, Optional

from sg3d.core.model import RELATION_TYPES
from sg3d.core.stored import NODE_FIELDS, StoredGraph, StoredObject, StoredRelation
from sg3d.graphdb.protocol import GraphStore
from sg3d.merge.histograms import unpack_hist


def fetch_graph(store: GraphStore, building: str, room: Optional[str] = None, thumbnails: bool = False,
                histograms: bool = False) -> StoredGraph:
    """The objects and relation edges of one room of `building` (or of all its rooms: room None);
    each object's histogram and thumbnail only when asked for."""
    nodes = []
    rows = store.read("export_objects", building=building, room=room)
    # the bytes live on Appearance nodes (schema 2): read only when asked for
    looks = {}
    if thumbnails or histograms:
        looks = {a["id"]: a for a in store.read("appearance_of", ids=[r["o"]["id"] for r in rows])}
    for row in rows:
        o = {**row["o"], **{k: v for k, v in looks.get(row["o"]["id"], {}).items() if v is not None}}
        added: dict[str, Any] = {}
        if histograms and o.get("hist") is not None:
            added["hist"] = [float(v) for v in unpack_hist(o["hist"])]
        if thumbnails and o.get("thumbnail"):
            added["thumbnail_jpeg_base64"] = base64.b64encode(bytes(o["thumbnail"])).decode()
        stored: dict[str, Any] = {k: o.get(k) for k in NODE_FIELDS}
        nodes.append(StoredObject(**stored, room_name=row["room"], **added))
    edges = [StoredRelation.from_row(r) for r in store.read("export_relations", building=building, room=room,
                                                            types=list(RELATION_TYPES))]
    return StoredGraph(building=building, room=room, nodes=nodes, edges=edges)
