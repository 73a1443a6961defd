"""sg3d.graphdb.values.jsonable: the one conversion of store and answer values to JSON."""
from __future__ import annotations

import json

from neo4j.time import Date

from sg3d.graphdb.values import jsonable


def test_jsonable_turns_every_kind_of_value_into_json():
    class Odd:
        def __str__(self):
            return "odd"

    value = {"b": b"\x00\x01\x02", 3: (1, 2.5, None, True), "d": Date(2026, 12, 1), "x": [Odd()]}
    out = jsonable(value)
    assert out == {"b": "<3 bytes>", "3": [1, 2.5, None, True], "d": "2026-12-01", "x": ["odd"]}
    assert json.loads(json.dumps(out)) == out


def test_rows_with_stored_nan_or_infinity_are_skipped_and_others_kept():
    from sg3d.graphdb.values import finite_rows, has_bad_number

    nan, inf = float("nan"), float("inf")
    good = [{"x": 1.0, "var": [0.1, 0.2, 0.3], "labels": ["cup", "mug"], "mixed": [1, "a", 2.5], "up": None}]
    bad = [{"x": inf}, {"var": [nan, 0.0, 0.0]}, {"o": {"size": [1.0, inf, 1.0]}}, {"mixed": ["a", nan]}]
    assert not any(has_bad_number(r) for r in good)
    assert all(has_bad_number(r) for r in bad)
    assert finite_rows(good + bad, "test") == good
