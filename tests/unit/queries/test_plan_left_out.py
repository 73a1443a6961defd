"""`sg3d plan` counts what its problem leaves out in one short line, by label, instead of listing
every wall and unnamed object with the same reason (no store: the Problem is data)."""
from __future__ import annotations

from sg3d.queries.planning.problem import Problem


def _problem(left: dict[str, tuple[str, str]]) -> Problem:
    return Problem(room="default/kitchen", objects=[], init=[], left_out={k: why for k, (_, why) in left.items()},
                   left_out_labels={k: label for k, (label, _) in left.items()})


def test_the_left_out_line_counts_by_label_and_names_only_what_is_out_of_reach():
    rule = "no planning rule for label"
    left = {f"wall_{i}": ("wall", f"{rule} 'wall'") for i in range(1, 7)}
    left |= {f"object_{i}": ("object", f"{rule} 'object'") for i in range(1, 32)}
    left |= {"floor": ("floor", f"{rule} 'floor'"), "counter": ("counter", f"{rule} 'counter'")}
    left |= {f"shelf_{i}": ("shelf", f"{rule} 'shelf'") for i in range(1, 4)}
    left |= {"tv": ("tv", f"{rule} 'tv'"), "grey_cup": ("cup", "not on or in anything the robot can reach in the graph")}
    line = _problem(left).left_out_summary()
    assert line.startswith("44 things left out: 31 unnamed objects, 6 walls, 3 shelves, "), line
    assert "the floor" in line and "grey cup" in line and "out of reach" in line, line
    assert "wall_1" not in line and "'wall'" not in line and len(line) < 200, line
    assert "\n" not in line


def test_nothing_left_out_is_an_empty_line():
    assert _problem({}).left_out_summary() == ""
