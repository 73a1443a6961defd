"""Reading a room's or a building's scene graph for export: {building, room, nodes, edges}, which
the `formats` package writes as the paper's JSON, GraphML, Spark-DSG or 3DSSG."""
from __future__ import annotations

import base64
from typing import Optional

from sg3d.core.model import RELATION_TYPES
from sg3d.merge.histograms import unpack_hist

NODE_FIELDS = ("id", "room", "label", "labels", "scores", "x", "y", "z", "var", "n_points", "size",
               "volume", "colour", "first_frame", "last_frame", "observations", "n_frames",
               "first_seen", "last_seen", "removed_at", "layer", "shape", "colour2", "named_by")


def fetch_graph(store, building: str, room: Optional[str] = None, thumbnails: bool = False,
                histograms: bool = False) -> dict:
    nodes = []
    rows = store.read("export_objects", building=building, room=room)
    # the bytes live on Appearance nodes (schema 2): read only when asked for
    looks = {}
    if thumbnails or histograms:
        looks = {a["id"]: a for a in store.read("appearance_of", ids=[r["o"]["id"] for r in rows])}
    for row in rows:
        o = {**row["o"], **{k: v for k, v in looks.get(row["o"]["id"], {}).items() if v is not None}}
        node = {k: o.get(k) for k in NODE_FIELDS}
        node["room_name"] = row["room"]
        if histograms and o.get("hist") is not None:
            node["hist"] = [float(v) for v in unpack_hist(o["hist"])]
        if thumbnails and o.get("thumbnail"):
            node["thumbnail_jpeg_base64"] = base64.b64encode(bytes(o["thumbnail"])).decode()
        nodes.append(node)
    edges = store.read("export_relations", building=building, room=room, types=list(RELATION_TYPES))
    return {"building": building, "room": room, "nodes": nodes, "edges": edges}
