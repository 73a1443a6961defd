"""The places layer of a recorded room in the store: the rooms found in its walk (WalkRoom nodes,
parts of the recorded Room), their doorways (Doorway nodes, CONNECTED both ways) and each
object IN_ROOM exactly one of them (not IN: that is the spatial relation between objects). Written whole in one transaction, replacing the last one."""
from __future__ import annotations

from typing import Any, Optional

from neo4j import ManagedTransaction

from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.merge import Fence
from sg3d.graphdb.protocol import GraphStore

WRITE_STEPS = ("places_rooms_create", "places_structure_create", "places_doorways_create", "places_objects_in")


def write_places(store: GraphStore, room: str, rooms: list[Row], doorways: list[Row], pairs: list[Row],
                 fence: Optional[Fence] = None) -> None:
    """Replace the places layer of recorded room `room` (its id): `rooms` rows of
    places_rooms_create (with `structure`: the ids of the floors and walls bounding each),
    `doorways` of places_doorways_create, `pairs` {object, room}; `fence` (the writer's lease,
    `sg3d.graphdb.lease.RoomLease.fence`) is checked first in the same transaction: a writer that
    lost the room writes nothing."""
    params: dict[str, dict[str, Any]] = {
        "places_rooms_create": {"rooms": rooms}, "places_structure_create": {"rooms": rooms},
        "places_doorways_create": {"doorways": doorways}, "places_objects_in": {"pairs": pairs}}

    def body(tx: ManagedTransaction) -> None:
        if fence is not None:
            fence(tx)
        tx.run(cypher.load("places_clear"), room=room).consume()
        for step in WRITE_STEPS:
            tx.run(cypher.load(step), room=room, **params[step]).consume()

    store.execute_write(body)


def read_places(store: GraphStore, room: str) -> list[Row]:
    """The rooms found in recorded room `room`'s walk, with their objects and doorways."""
    return store.read("places_rooms", room=room)


def object_rooms(store: GraphStore, room: str) -> list[Row]:
    """Every object of recorded room `room` with the names of the found rooms it is IN."""
    return store.read("places_object_rooms", room=room)


def rename_place(store: GraphStore, room: str, place: str, name: str) -> None:
    """The found room `place` (its id) of recorded room `room` is called `name` from now on; the
    recorded room's revision goes up in the same transaction."""
    store.execute_write(lambda tx: tx.run(cypher.load("places_rename"), room=room, id=place, name=name).consume())
