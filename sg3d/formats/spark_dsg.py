"""spark_dsg (the scene-graph format of Hydra, Clio, Heracles): our exported graph as a
`spark_dsg.DynamicSceneGraph`, and a spark_dsg file back as local graphs to merge.

Mapping (also on the docs' formats page):
- layer OBJECTS (2): one node per object, symbol ``O<k>``; ``semantic_label`` = the label's
  index in the graph's labelspace (metadata ``labelspace``, id -> name, also set with
  ``set_labelspace`` on layer 2), ``name`` = the readable name, ``position`` = the Gaussian
  mean, ``bounding_box`` = axis-aligned box (size w, d, h around the mean), ``color`` = RGB of the
  dominant colour name; node metadata ``sg3d``: id, room, labels, scores, var, n_points, colour,
  observations, frames and the 512-bin HSV histogram (so an import loses nothing).
- layer 1 (structure): the room's floor, walls and surfaces, symbol ``S<k>``, attributes as
  objects; objects' ON edges reach them (an import reads them back when they carry sg3d's
  metadata; another tool's layer 1 is not read).
- layer ROOMS (4): one node per room, symbol ``R<k>``, position = mean of its objects, box =
  their extent; an interlayer edge to each of its objects.
- layer BUILDINGS (5): one node ``B0`` (the building), an interlayer edge to each room.
- our relations: spark_dsg graphs are undirected with one edge per pair, so every relation of a
  pair goes into that edge's metadata ``relations`` [{subject, predicate, object, score}]
  (directed by subject/object ids); the edge weight is the best score.
- positions are in the building frame: a room with a stored room-to-building transform is
  moved by it (otherwise the room's own frame, which is the building's for the first room).
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Optional

import numpy as np

from sg3d.core.errors import Sg3dError
from sg3d.core.model import COLOUR_NAMES, HIST_SIZE, RELATION_TYPES
from sg3d.core.stored import Row, StoredGraph

OBJECTS, PLACES, ROOMS, BUILDINGS = 2, 3, 4, 5
# The room's structure (floor, walls, counters, shelves) is a layer of its own, below the
# objects that stand on it; `read_spark` reads the objects layer only.
STRUCTURE = 1

# sRGB of each colour name (the hue bands of sg3d.ingest.objects.attributes), for spark_dsg's node colour
COLOUR_RGB = {"red": (220, 30, 30), "orange": (245, 140, 20), "yellow": (240, 220, 40), "green": (40, 170, 60),
              "blue": (40, 90, 220), "purple": (130, 50, 180), "pink": (240, 130, 190), "brown": (130, 80, 40),
              "black": (20, 20, 20), "white": (245, 245, 245), "grey": (128, 128, 128)}
assert set(COLOUR_RGB) == set(COLOUR_NAMES)


class SparkError(Sg3dError, ValueError):
    """A file that is not a spark_dsg scene graph we can read."""


def _spark():
    try:
        import spark_dsg
    except ImportError:  # pragma: no cover - a dependency; only missing in a broken install
        raise SparkError("the spark-dsg package is not installed (pip install spark-dsg)") from None
    return spark_dsg


def _apply(T: Optional[np.ndarray], p) -> np.ndarray:
    p = np.asarray(p, dtype=np.float64)
    return p if T is None else T[:3, :3] @ p + T[:3, 3]


def to_spark(graph: StoredGraph, room_transforms: Optional[dict] = None):
    """The exported graph (`sg3d.graphdb.export.fetch_graph`, named) as a DynamicSceneGraph;
    `room_transforms`: room name -> 4x4 room-to-building (or None)."""
    dsg = _spark()
    G = dsg.DynamicSceneGraph()
    labels = sorted({n.label or "object" for n in graph.nodes})
    label_id = {name: i for i, name in enumerate(labels)}
    rooms = sorted({n.room_name or "" for n in graph.nodes})
    given = room_transforms or {}
    transforms = {r: (None if given.get(r) is None else np.asarray(given[r], dtype=float))
                  for r in rooms}
    symbols = {}
    by_room: dict[str, list[np.ndarray]] = {r: [] for r in rooms}
    boxes: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {r: [] for r in rooms}
    for k, n in enumerate(graph.nodes):
        room = n.room_name or ""
        a = dsg.ObjectNodeAttributes()
        a.semantic_label = label_id[n.label or "object"]
        a.name = n.name or n.id
        p = _apply(transforms[room], (n.x, n.y, n.z))
        a.position = p
        size = np.asarray(n.size or (0.0, 0.0, 0.0), dtype=np.float32)
        a.bounding_box = dsg.BoundingBox(size, p.astype(np.float32))
        a.color = np.array(COLOUR_RGB.get(n.colour or "grey", COLOUR_RGB["grey"]), dtype=np.uint8)
        meta: Row = {"id": n.id, "room": room, "labels": n.labels or [n.label],
                "scores": n.scores or [], "var": n.var, "n_points": n.n_points,
                "colour": n.colour, "observations": n.observations,
                "first_frame": n.first_frame, "last_frame": n.last_frame,
                "layer": n.layer, "shape": n.shape, "colour2": n.colour2}
        if n.hist is not None:
            meta["hist"] = [float(v) for v in n.hist]
        a.metadata.set({"sg3d": {k2: v for k2, v in meta.items() if v is not None}})
        structure = n.layer == "structure"
        sym = dsg.NodeSymbol("S" if structure else "O", k)
        G.add_node(STRUCTURE if structure else OBJECTS, sym, a)
        symbols[n.id] = sym
        by_room[room].append(p)
        boxes[room].append((p - size / 2, p + size / 2))
    building = dsg.SemanticNodeAttributes()
    building.name = graph.building
    centres = []
    for k, room in enumerate(rooms):
        r = dsg.RoomNodeAttributes()
        r.name = room
        centre = np.mean(by_room[room], axis=0)
        r.position = centre
        lo = np.min([b[0] for b in boxes[room]], axis=0)
        hi = np.max([b[1] for b in boxes[room]], axis=0)
        r.bounding_box = dsg.BoundingBox((hi - lo).astype(np.float32), ((hi + lo) / 2).astype(np.float32))
        r.metadata.set({"sg3d": {"room": room, "building": graph.building}})
        G.add_node(ROOMS, dsg.NodeSymbol("R", k), r)
        centres.append(centre)
    building.position = np.mean(centres, axis=0) if centres else np.zeros(3)
    building.metadata.set({"sg3d": {"building": graph.building}})
    G.add_node(BUILDINGS, dsg.NodeSymbol("B", 0), building)
    for k, room in enumerate(rooms):
        G.insert_edge(dsg.NodeSymbol("B", 0), dsg.NodeSymbol("R", k))
    room_sym = {room: dsg.NodeSymbol("R", k) for k, room in enumerate(rooms)}
    for n in graph.nodes:
        G.insert_edge(room_sym[n.room_name or ""], symbols[n.id])
    pairs: dict[tuple[str, ...], list[Row]] = {}
    for e in graph.edges:
        if e.s in symbols and e.o in symbols:
            pairs.setdefault(tuple(sorted((e.s, e.o))), []).append(
                {"subject": e.s, "predicate": e.type, "object": e.o, "score": e.score})
    for (a_id, b_id), rels in pairs.items():
        info = dsg.EdgeAttributes()
        info.weighted = True
        info.weight = max((r["score"] or 0.0) for r in rels)
        info.metadata.set({"relations": rels})
        G.insert_edge(symbols[a_id], symbols[b_id], info)
    G.set_labelspace(dsg.Labelspace(dict(enumerate(labels))), OBJECTS)
    G.metadata.add({"sg3d": {"building": graph.building, "room": graph.room,
                             "labelspace": {str(i): name for i, name in enumerate(labels)}}})
    return G


def to_spark_json(graph: StoredGraph, room_transforms: Optional[dict] = None) -> str:
    """The graph as spark_dsg's JSON text (what `DynamicSceneGraph.save("x.json")` writes)."""
    G = to_spark(graph, room_transforms)
    fd, tmp = tempfile.mkstemp(suffix=".json")
    os.close(fd)
    try:
        G.save(tmp, include_mesh=False)
        return Path(tmp).read_text()
    finally:
        os.unlink(tmp)


# -- import ----------------------------------------------------------------------------------

def _label_names(G) -> dict[int, str]:
    meta = G.metadata.get() or {}
    names = {int(k): v for k, v in ((meta.get("sg3d") or {}).get("labelspace") or {}).items()}
    if names:
        return names
    try:  # Hydra stores the labelspace of the objects layer with set_labelspace
        space = G.get_labelspace(OBJECTS, 0)
        if space is not None:
            return {int(k): v for k, v in space.labels_to_names.items()}
    except Exception:
        pass
    return {}


def _nearest_colour(rgb) -> str:
    rgb = np.asarray(rgb, dtype=float)[:3]
    return min(COLOUR_RGB, key=lambda c: float(np.sum((np.asarray(COLOUR_RGB[c], float) - rgb) ** 2)))


def colour_hist(rgb) -> list[float]:
    """An 8x8x8 HSV histogram (the layout of sg3d.ingest.objects.attributes: OpenCV H 0-179, S, V 0-255) with
    all mass in the bin of one RGB colour: what a graph without histograms tells of colour."""
    import colorsys

    r, g, b = (float(v) / 255.0 for v in np.asarray(rgb, dtype=float)[:3])
    h, s, v = colorsys.rgb_to_hsv(r, g, b)
    hist = [0.0] * HIST_SIZE
    hb, sb, vb = min(int(h * 8), 7), min(int(s * 8), 7), min(int(v * 8), 7)
    hist[(hb * 8 + sb) * 8 + vb] = 1.0
    return hist


def read_spark(path) -> dict:
    """A spark_dsg file -> {"building": name, "rooms": {room name: {"objects": [...],
    "relations": [...]}}} in the `POST /ingest` graph schema (sg3d.app.ingest.LocalGraphIn).
    Objects without a room parent go to the room named ""; relations are kept between objects
    of one room only (a local graph is one room's)."""
    dsg = _spark()
    path = Path(path)
    if not path.is_file():
        raise SparkError(f"spark_dsg file not found: {path}")
    try:
        G = dsg.DynamicSceneGraph.load(str(path))
    except Exception as exc:
        raise SparkError(f"cannot read {path} as a spark_dsg scene graph: {exc}") from None
    if not G.has_layer(OBJECTS) or G.get_layer(OBJECTS).num_nodes() == 0:
        raise SparkError(f"{path} holds no nodes in the objects layer (2)")
    names = _label_names(G)
    room_name: dict[int, str] = {}
    if G.has_layer(ROOMS):
        for node in G.get_layer(ROOMS).nodes:
            meta = (node.attributes.metadata.get() or {}).get("sg3d") or {}
            room_name[node.id.value] = meta.get("room") or node.attributes.name or node.id.str()
    building = ""
    if G.has_layer(BUILDINGS):
        for node in G.get_layer(BUILDINGS).nodes:
            meta = (node.attributes.metadata.get() or {}).get("sg3d") or {}
            building = meta.get("building") or node.attributes.name or node.id.str()
            break
    rooms: dict[str, dict] = {}
    where: dict[int, tuple[str, str]] = {}      # node id -> (room, object id)
    ours_structure = [node for node in (G.get_layer(STRUCTURE).nodes if G.has_layer(STRUCTURE) else [])
                      if ((node.attributes.metadata.get() or {}).get("sg3d") or {}).get("layer") == "structure"]
    for node in list(G.get_layer(OBJECTS).nodes) + ours_structure:
        a = node.attributes
        meta = (a.metadata.get() or {}).get("sg3d") or {}
        parent = node.get_parent()
        # structure nodes hang below the objects layer, so their room is in sg3d's metadata
        room = room_name.get(parent, "") if parent is not None else (meta.get("room") or "")
        label = names.get(int(a.semantic_label)) or a.name or "object"
        oid = meta.get("id") or node.id.str()
        pos = np.asarray(a.position, dtype=float)
        box = a.bounding_box
        size = [float(v) for v in np.asarray(box.dimensions)] if box.is_valid() else [0.0, 0.0, 0.0]
        labels = meta.get("labels") or [label]
        scores = meta.get("scores") or [1.0] * len(labels)
        rgb = np.asarray(a.color, dtype=float)
        obj = {"id": oid, "labels": labels, "scores": scores[:len(labels)],
               "mean": [float(v) for v in pos], "var": meta.get("var") or [0.01, 0.01, 0.01],
               "n_points": int(meta.get("n_points") or 100), "size": size,
               "hist": meta.get("hist") or colour_hist(rgb),
               "colour": meta.get("colour") or _nearest_colour(rgb)}
        for key in ("layer", "shape", "colour2"):      # sg3d's own export: nothing lost
            if meta.get(key):
                obj[key] = meta[key]
        rooms.setdefault(room, {"objects": [], "relations": []})["objects"].append(obj)
        where[node.id.value] = (room, oid)
    for edge in G.edges:
        if edge.source not in where or edge.target not in where:
            continue
        (room_a, _), (room_b, _) = where[edge.source], where[edge.target]
        if room_a != room_b:
            continue
        for rel in (edge.info.metadata.get() or {}).get("relations") or []:
            if rel.get("predicate") in RELATION_TYPES:
                rooms[room_a]["relations"].append({"subject": rel["subject"], "predicate": rel["predicate"],
                                                   "object": rel["object"],
                                                   "score": float(rel.get("score") or 1.0)})
    return {"building": building, "rooms": rooms, "layers": {int(k.layer): G.get_layer(k.layer).num_nodes()
                                                             for k in G.layer_keys}}

