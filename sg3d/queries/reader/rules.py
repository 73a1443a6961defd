"""The table of rewrites (sg3d/queries/data/rephrase_rules.toml) that turns people's phrasing into
the plain text the grammar reads, and the engine that applies it.

The table is data: each rule is a regular expression and its replacement (or the name of a step
written in Python, `steps.STEPS`, where a rewrite needs more than one substitution), with why it
is there and examples that are its tests (tests/unit/queries/test_rephrase_rules.py). Rules belong
to stages; the file's `order` says in which order the stages run (a stage may run more than
once), and a rule's `after` names the rules it must come after (checked by the test).
"""
from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from typing import Callable, Literal, Optional

from sg3d.queries.reader.data import rules_file

_MACRO = re.compile(r"\{([a-z_]+)\}")

Replacement = str | Callable[[re.Match[str]], str]


@dataclass(frozen=True)
class Rule:
    """One row of the table: a substitution (`regex`, `replace`) or a named step (`call`)."""

    name: str
    stage: str
    why: str
    examples: tuple[dict, ...]
    regex: Optional[re.Pattern[str]] = None
    replace: Replacement = ""
    call: Optional[str] = None
    yields: Literal["text", "notes", "dropped"] = "text"
    strip: Optional[str] = None
    after: tuple[str, ...] = ()

    def apply(self, text: str) -> tuple[str, list[str]]:
        """`text` rewritten by this rule, and the notes (or dropped asides) it gives."""
        if self.call is not None:
            from sg3d.queries.reader.steps import STEPS

            out = STEPS[self.call](text)
            return out if isinstance(out, tuple) else (out, [])
        assert self.regex is not None
        text = self.regex.sub(self.replace, text)
        if self.strip is not None:
            text = text.strip(self.strip) if self.strip else text.strip()
        return text, []


@dataclass(frozen=True)
class Table:
    rules: tuple[Rule, ...]
    order: tuple[str, ...]
    repeat: frozenset[str]

    def stage(self, name: str) -> tuple[Rule, ...]:
        return tuple(r for r in self.rules if r.stage == name)

    def rule(self, name: str) -> Rule:
        return next(r for r in self.rules if r.name == name)


def alternation(words, longest_first: bool = True) -> str:
    """`words` as a regular-expression alternation (escaped; longest first, so a phrase wins over
    its first word)."""
    words = list(words)
    if longest_first:
        words = sorted(words, key=len, reverse=True)
    return "|".join(map(re.escape, words))


def _expand(pattern: str, macros: dict[str, str]) -> str:
    """The pattern with each `{name}` of the table's `macros` (word lists of the table and of the
    lexicon) filled in; a regular expression's own `{1,3}` holds digits and is left alone."""
    return _MACRO.sub(lambda m: macros[m.group(1)], pattern)


def _macros(data: dict) -> dict[str, str]:
    from sg3d.queries import vocabulary as v

    lists = data["words"] | data["dictionaries"]
    macros = {name: alternation(words, longest_first=False) for name, words in lists.items()}
    macros |= {f"{name}_longest": alternation(words) for name, words in lists.items()}
    macros |= data["fragments"]
    macros |= {"room_words": alternation(v.ROOM_WORDS), "relation_words": alternation(v.RELATIONS),
               "adjectives": alternation(sorted(set(v.COLOURS) | set(v.SIZES)))}
    return macros


def _rules_of(row: dict, data: dict, macros: dict[str, str]) -> list[Rule]:
    """The rules of one row of the table: one, or one per word of a dictionary (`each`)."""
    from sg3d.queries.reader.steps import REPLACERS

    common = dict(name=row["name"], stage=row["stage"], why=row["why"],
                  examples=tuple(row.get("examples", ())), yields=row.get("yields", "text"),
                  strip=row.get("strip"), after=tuple(row.get("after", ())))
    if "call" in row:
        return [Rule(call=row["call"], **common)]
    if "each" in row:
        words = data["dictionaries"][row["each"]]
        if row.get("each_order") == "longest":
            words = {w: words[w] for w in sorted(words, key=len, reverse=True)}
        return [Rule(regex=re.compile(_expand(row["pattern"].replace("{word}", re.escape(w)), macros)),
                     replace=row["replace"].replace("{value}", words[w]), **common) for w in words]
    repl: Replacement = REPLACERS[row["replace_with"]] if "replace_with" in row else row.get("replace", "")
    return [Rule(regex=re.compile(_expand(row["pattern"], macros)), replace=repl, **common)]


@functools.cache
def table() -> Table:
    """The rewrite table, read and compiled once per process."""
    data = rules_file()
    macros = _macros(data)
    rules = tuple(r for row in data["rule"] for r in _rules_of(row, data, macros))
    return Table(rules, tuple(data["order"]), frozenset(data.get("repeat", ())))


def misordered(t: Table) -> list[str]:
    """What breaks the table's order: a stage whose rules are not written together, or a rule
    that runs before one it names in `after` (empty when the order holds)."""
    stages = list(dict.fromkeys(r.stage for r in t.rules))
    wrong = [] if [s for i, s in enumerate(t.order) if s not in t.order[:i]] == stages else ["stages"]
    first = {r.name: t.order.index(r.stage) * 1000 + i for i, r in enumerate(t.rules)}
    return wrong + [f"{r.name} after {a}" for r in t.rules for a in r.after if first[a] >= first[r.name]]


def run_stage(name: str, text: str, trace: Optional[list] = None) -> tuple[str, list[str]]:
    """`text` through the rules of one stage, in the table's order (again until nothing changes
    for a stage listed in `repeat`); the notes the rules gave. `trace` collects (rule, before,
    after) for each rule that changed the text."""
    rules = table().stage(name)
    notes: list[str] = []
    prev = None
    while prev != text:
        prev = text
        for rule in rules:
            before = text
            text, more = rule.apply(text)
            notes += more
            if trace is not None and text != before:
                trace.append((rule.name, before, text))
        if name not in table().repeat:
            break
    return text, notes
