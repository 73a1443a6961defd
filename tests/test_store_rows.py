"""`Store.read`'s rows (`plain_rows`) equal the driver's own `Result.data()` on a real store: scene
reads (lists of numbers), a map projection with bytes (`object_all`), a node returned whole."""
from __future__ import annotations

from sg3d.graphdb import cypher
from sg3d.graphdb.store import plain_rows
from sg3d.graphdb.values import room_id
from sg3d.queries.vocabulary import STORED_TYPES

KITCHEN = room_id("home", "kitchen")


def _both(store, text: str, params: dict):
    with store.session() as s:
        return (s.execute_read(lambda tx: plain_rows(tx.run(text, params))),
                s.execute_read(lambda tx: tx.run(text, params).data()))


def test_plain_rows_are_the_drivers_rows(house, store):
    ids = sorted(house.values())
    for name, params in (("vqa_scene_objects_in_rooms", {"rooms": [KITCHEN], "labels": None, "limit": 1000}),
                         ("vqa_scene_relations", {"ids": ids, "types": list(STORED_TYPES)}),
                         ("object_all", {"room": KITCHEN})):
        mine, drivers = _both(store, cypher.load(name), params)
        assert mine and mine == drivers, name
    mine, drivers = _both(store, "MATCH (r:Room) RETURN r, r.id AS id ORDER BY id", {})   # a node: the driver's dict
    assert mine == drivers and isinstance(mine[0]["r"], dict)
