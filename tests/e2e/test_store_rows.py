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


def _one_row_each(text: str) -> str:
    """The statement of a collected template (`RETURN collect({k: expr, ...}) AS rows`) with one
    row per map instead (`RETURN expr AS k, ...`): what the template returned before it collected."""
    head, _, tail = text.rpartition("RETURN collect({")
    fields, depth, part = [], 0, ""
    for ch in tail.rsplit("}) AS rows", 1)[0]:
        depth += ch in "([{"
        depth -= ch in ")]}"
        if ch == "," and depth == 0:
            fields.append(part)
            part = ""
        else:
            part += ch
    fields.append(part)
    pairs = [f.split(":", 1) for f in fields]
    return head + "RETURN " + ", ".join(f"{expr.strip()} AS {key.strip()}" for key, expr in pairs)


def test_a_collected_template_reads_as_the_rows_it_collected(house, store):
    """A template that returns its rows in one list (`cypher.collected`) reads as those rows, each
    with every field (null ones too), in the order the template gives them: what the same
    statement returning one row per map gives."""
    from sg3d.core.model import UNNAMED_LABEL
    from sg3d.queries.naming import SUPPORT_TYPES

    ids = sorted(house.values())
    cases = {"naming_objects": {"rooms": [KITCHEN], "labels": ["chair", "cup", "bowl", "dining table"],
                                "support_types": list(SUPPORT_TYPES)},
             "vqa_scene_linked": {"ids": ids, "types": list(STORED_TYPES), "rooms": [KITCHEN]},
             "vqa_scene_objects_in_rooms": {"rooms": [KITCHEN], "labels": None, "limit": 1000},
             "vqa_unnamed": {"unnamed": UNNAMED_LABEL, "rooms": None, "support_types": list(SUPPORT_TYPES),
                             "limit": 1000}}
    collected = [n for n in cases if cypher.collected(n)]
    assert collected == list(cases)
    for name, params in cases.items():
        each, _ = _both(store, _one_row_each(cypher.load(name)), params)
        assert store.read(name, **params) == each, name
        assert each or name == "vqa_unnamed", name
