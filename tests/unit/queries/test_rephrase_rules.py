"""The rewrite table (sg3d/queries/data/rephrase_rules.toml): every rule's examples run through the
rule alone and through the whole reader, and the table's order is the order its rules need."""
from __future__ import annotations

from dataclasses import replace

import pytest

from sg3d.queries.reader.rules import misordered, table
from sg3d.queries.reader.tidy import traced

NAMES = list(dict.fromkeys(r.name for r in table().rules))
EXAMPLES = [(name, e) for name in NAMES for e in table().rule(name).examples]


def _rule(name: str, text: str) -> str:
    """`text` through the rule `name` (every word of a dictionary rule, in the table's order)."""
    for rule in table().rules:
        if rule.name == name:
            text = rule.apply(text)[0]
    return text


def test_every_rule_has_a_reason_and_an_example():
    assert not [n for n in NAMES if not table().rule(n).why.strip() or not table().rule(n).examples]


@pytest.mark.parametrize("name,example", EXAMPLES, ids=[f"{n}:{e['at'][:40]}" for n, e in EXAMPLES])
def test_a_rule_gives_its_example(name, example):
    assert _rule(name, example["at"]) == example["gives"]


@pytest.mark.parametrize("name,example", [(n, e) for n, e in EXAMPLES if "said" in e],
                         ids=[f"{n}:{e['said'][:40]}" for n, e in EXAMPLES if "said" in e])
def test_the_reader_reads_an_example_through_its_rule(name, example):
    trace: list = []
    assert traced(example["said"], trace).text == example["reads"]
    assert any(rule == name and before == example["at"] for rule, before, _ in trace)


def test_the_stages_run_in_the_order_written_and_each_rule_after_those_it_names():
    assert misordered(table()) == []


def test_a_rule_moved_before_one_it_needs_is_caught():
    t = table()
    order = list(t.order)
    order[order.index("posture")], order[order.index("place-to")] = "place-to", "posture"
    assert misordered(replace(t, order=tuple(order)))
