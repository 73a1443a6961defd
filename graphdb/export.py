"""Exporting a room's or a building's scene graph: the paper's JSON (Sec. VII-A.4) or GraphML."""
from __future__ import annotations

import base64
import json
import xml.etree.ElementTree as ET
from typing import Optional

from graphdb.values import unpack_hist
from ingest.model import RELATION_TYPES

NODE_FIELDS = ("id", "room", "label", "labels", "scores", "x", "y", "z", "var", "n_points", "size",
               "volume", "colour", "first_frame", "last_frame", "observations", "n_frames",
               "first_seen", "last_seen", "removed_at", "layer", "shape", "colour2")


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


def to_json(graph: dict) -> str:
    return json.dumps(graph, indent=1)


def to_graphml(graph: dict) -> str:
    root = ET.Element("graphml", xmlns="http://graphml.graphdrawing.org/xmlns")
    scalar = {"label": "string", "name": "string", "room_name": "string", "colour": "string", "x": "double", "y": "double",
              "z": "double", "volume": "double", "observations": "int", "layer": "string"}
    for name, kind in scalar.items():
        ET.SubElement(root, "key", id=name, attrib={"for": "node", "attr.name": name, "attr.type": kind})
    ET.SubElement(root, "key", id="type", attrib={"for": "edge", "attr.name": "type", "attr.type": "string"})
    ET.SubElement(root, "key", id="score", attrib={"for": "edge", "attr.name": "score", "attr.type": "double"})
    g = ET.SubElement(root, "graph", id=graph["building"], edgedefault="directed")
    for node in graph["nodes"]:
        n = ET.SubElement(g, "node", id=node["id"])
        for name in scalar:
            if node.get(name) is not None:
                ET.SubElement(n, "data", key=name).text = str(node[name])
    for i, edge in enumerate(graph["edges"]):
        e = ET.SubElement(g, "edge", id=f"e{i}", source=edge["s"], target=edge["o"])
        ET.SubElement(e, "data", key="type").text = edge["type"]
        ET.SubElement(e, "data", key="score").text = str(edge["score"])
    ET.indent(root)
    return ET.tostring(root, encoding="unicode", xml_declaration=True)
