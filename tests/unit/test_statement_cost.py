"""The statement guard of the user-Cypher paths (`sg3d cypher`, the shell, MCP, HTTP): ranges that
would build more items than the store can stop are refused; both sides of each bound pinned."""
from __future__ import annotations

import pytest

from sg3d.app.errors import Refused
from sg3d.app.graph import MAX_RANGE_ITEMS, MAX_RANGE_WORK, check_statement, range_work


def test_one_range_at_and_over_the_bound():
    check_statement(f"RETURN size(range(1, {MAX_RANGE_ITEMS}))")
    with pytest.raises(Refused, match="holds"):
        check_statement(f"RETURN size(range(1, {MAX_RANGE_ITEMS + 1}))")


def test_nested_ranges_multiply():
    side = int(MAX_RANGE_WORK ** 0.5)
    check_statement(f"RETURN reduce(s=0, x IN range(1,{side}) | s + reduce(t=0, y IN range(1,{side}) | t+y))")
    with pytest.raises(Refused, match="multiply"):
        check_statement("RETURN reduce(s=0, x IN range(1,10000) | s + reduce(t=0, y IN range(1,20000) | t+y))")


def test_bounds_given_as_parameters_count_and_strings_do_not():
    with pytest.raises(Refused):
        check_statement("RETURN size([x IN range(1, $n) | toString(x)])", {"n": 26_000_000})
    check_statement("RETURN size([x IN range(1, $n) | toString(x)])", {"n": 10})
    check_statement("RETURN 'range(1, 99999999)' AS text")
    assert range_work("RETURN range(0, 100, 10)", {}) == (11, 11)
    assert range_work("MATCH (o) RETURN o", {}) == (0, 0)


def test_an_unwound_range_makes_rows_the_time_limit_stops():
    check_statement("UNWIND range(1, 10000000) AS x RETURN count(x) AS n")
    with pytest.raises(Refused):
        check_statement("UNWIND range(1, 3) AS k RETURN size([x IN range(1, 26000000) | toString(x)])")
