"""graphdb.values.jsonable: the one conversion of store and answer values to JSON."""
from __future__ import annotations

import json

from neo4j.time import Date

from graphdb.values import jsonable


def test_jsonable_turns_every_kind_of_value_into_json():
    class Odd:
        def __str__(self):
            return "odd"

    value = {"b": b"\x00\x01\x02", 3: (1, 2.5, None, True), "d": Date(2026, 12, 1), "x": [Odd()]}
    out = jsonable(value)
    assert out == {"b": "<3 bytes>", "3": [1, 2.5, None, True], "d": "2026-12-01", "x": ["odd"]}
    assert json.loads(json.dumps(out)) == out
