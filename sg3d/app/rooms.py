"""Rooms and their objects: what `sg3d rooms`, `GET /rooms`, `GET /rooms/{building}/{room}/objects`
and the MCP `list_rooms` / `list_objects` tools return."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

from sg3d.app import bounds
from sg3d.app.ask import MAX_SCOPE_CHARS
from sg3d.app.errors import AppError, NotFound
from sg3d.core.stored import Row
from sg3d.graphdb.protocol import GraphStore

OBJECT_LIMIT = 10_000   # objects one listing returns at most


def filter_problem(label: object = None, colour: object = None, building: object = None,
                   room: object = None) -> Optional[str]:
    """Why a listing cannot be asked for with these, or None. Rule: a label or colour is a text of
    at most `bounds.MAX_LABEL_CHARS` characters, a building or room (a name or an id) at most
    `MAX_SCOPE_CHARS`: the bounds of `GET /rooms...` too, here so that every front end (HTTP, MCP,
    CLI) keeps them. The reason names the length and the limit, never the value."""
    return bounds.length_problem((("label", label, bounds.MAX_LABEL_CHARS), ("colour", colour, bounds.MAX_LABEL_CHARS),
                                  ("building", building, MAX_SCOPE_CHARS), ("room", room, MAX_SCOPE_CHARS)))


def _check_filters(**values) -> None:
    problem = filter_problem(**values)
    if problem:
        raise AppError(problem)


def rooms_json(rows: list[Row]) -> list[Row]:
    """Rooms as JSON: id, name, objects, to_building (4x4 as lists or null), adjacent names."""
    return [{"id": r["id"], "name": r["name"], "objects": r["objects"],
             "to_building": None if r["to_building"] is None else r["to_building"].tolist(),
             "adjacent": r["adjacent"]} for r in rows]


def frame_words(to_building) -> str:
    """Which frame a room is in, for `sg3d rooms`: the building's reference (the identity: the first
    room placed), placed in it (by --shared-frame, --transform, --align-to or `rooms link`), or its own."""
    if to_building is None:
        return "own frame (not placed in the building)"
    import numpy as np

    if np.allclose(np.asarray(to_building, float).reshape(4, 4), np.eye(4), atol=1e-9):
        return "the building's reference frame"
    return "placed in the building's frame"


def building_rooms(store: GraphStore, building: str) -> list[Row]:
    """The rooms of one building (graphdb rows, transforms as arrays)."""
    from sg3d.graphdb.building import list_rooms

    return list_rooms(store, building)


def list_rooms(store: GraphStore, building: Optional[str] = None) -> list[Row]:
    """Rooms as JSON (`rooms_json`) with their building: one building's, or every building's."""
    _check_filters(building=building)
    buildings = [building] if building else sorted({r["building"] for r in store.read("plan_rooms")})
    return [{"building": b, **r} for b in buildings for r in rooms_json(building_rooms(store, b))]


def _near(near: Optional[Sequence[float]], radius: Optional[float]):
    if near is None:
        if radius is not None:
            raise AppError("radius needs a point: give near=x,y,z")
        return None
    if len(near) != 3 or not all(math.isfinite(float(v)) for v in near):
        raise AppError("near must be three finite numbers x,y,z (metres, the room's frame)")
    if radius is not None and not (radius > 0 and math.isfinite(radius)):
        raise AppError("radius must be a positive number of metres")
    return [float(v) for v in near]


@dataclass(frozen=True)
class ObjectFilter:
    """Which objects of a room: by best label, colour name and distance from a point (`near` x,y,z
    in the room's frame; `radius` metres, default: no bound, sorted nearest first), at most `limit`."""

    label: Optional[str] = None
    colour: Optional[str] = None
    near: Optional[Sequence[float]] = None
    radius: Optional[float] = None
    limit: int = OBJECT_LIMIT


def room_objects(store: GraphStore, building: str, room: str, only: ObjectFilter = ObjectFilter()) -> list[Row]:
    """The objects of one room with their readable names, filtered by `only`. NotFound when the
    room is not in the store."""
    label, colour, near, radius, limit = only.label, only.colour, only.near, only.radius, only.limit
    from sg3d.graphdb.values import room_id
    from sg3d.queries.naming import names_in_store

    _check_filters(label=label, colour=colour, building=building, room=room)
    point = _near(near, radius)
    rid = room_id(building, room)
    if not store.read("building_room_get", room=rid):
        raise NotFound(f"no room {rid!r} in the store")
    rows = store.read("vqa_objects_in_rooms", rooms=[rid], labels=[label.strip().lower()] if label else None,
                      colour=colour.strip().lower() if colour else None, limit=limit)
    names = names_in_store(store.read, rows)
    out = []
    for r in rows:
        item = {"id": r["id"], "name": names.get(r["id"], r["label"]), "label": r["label"], "colour": r["colour"],
                "position": [r["x"], r["y"], r["z"]], "size": r["size"], "volume": r["volume"],
                "score": r["score"], "room": r["room"]}
        if point is not None:
            item["distance"] = round(math.dist(point, item["position"]), 4)
            if radius is not None and item["distance"] > radius:
                continue
        out.append(item)
    if point is not None:
        out.sort(key=lambda o: o["distance"])
    return out


DELETE_BATCH = 2000   # objects removed per statement when a room is deleted (all in one transaction)

# What deleting a room removes after its objects, in this order, in the objects' transaction.
DELETE_STEPS = ("room_delete_tallies", "room_delete_merge_logs", "room_delete_scans", "places_clear",
                "room_delete_node")


def delete_room_in_tx(tx, rid: str, batch: Optional[int] = None) -> int:
    """The body of the delete transaction: the room's objects (with their Appearance nodes and
    every edge, `batch` per statement), tallies, merge logs, scans, the rooms found in its walk
    (`--rooms auto`) and the room node. Returns the
    objects removed."""
    from sg3d.graphdb import cypher

    batch = batch or DELETE_BATCH
    objects = 0
    while True:
        n = tx.run(cypher.load("room_delete_objects"), room=rid, batch=batch).single()["n"]
        objects += n
        if n < batch:
            break
    for template in DELETE_STEPS:
        tx.run(cypher.load(template), room=rid).consume()
    return objects


def delete_room(store: GraphStore, building: str, room: str) -> dict:
    """Remove one room: its objects (with their Appearance nodes and edges), tallies, merge logs,
    scans and the room node; nothing of any other room. ONE transaction: interrupted at any point
    (kill -9, a lost connection), the store holds the whole room or none of it. NotFound when it
    is not in the store. Returns what was removed: {room, objects}."""
    from sg3d.graphdb.values import room_id

    rid = room_id(building, room)
    if not store.read("building_room_get", room=rid):
        raise NotFound(f"no room {rid!r} in the store")
    objects = store.execute_write(lambda tx: delete_room_in_tx(tx, rid))
    store.rooms_known.discard(rid)
    return {"room": rid, "objects": objects}
