"""The logical form of a question: sets of objects filtered by relations, and one operation.

Plain data the grammar (sg3d/queries/grammar.py) produces and the compiler (sg3d/queries/compose.py)
answers. Words are kept as they were read, so a refusal can name the one it did not understand.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional


@dataclass
class Filter:
    """A restriction of a set by another set: a stored relation, or a distance band."""

    kind: str                               # rel | distance
    other: "NP"
    relation: Optional[str] = None          # the relation word ("next to") when kind == rel
    low_m: Optional[float] = None           # distance band, metres (centre to centre)
    high_m: Optional[float] = None
    negated: bool = False

    def describe(self, other: Optional[str] = None) -> str:
        """The filter in words; `other` names the other set (default: its own description)."""
        neg = "not " if self.negated else ""
        other = self.other.describe() if other is None else other
        if self.kind == "rel":
            return f"{neg}{self.relation} {other}"
        if self.low_m is None:
            return f"{neg}within {fmt_m(self.high_m)} of {other}"
        if self.high_m is None:
            return f"{neg}farther than {fmt_m(self.low_m)} from {other}"
        return f"{neg}between {fmt_m(self.low_m)} and {fmt_m(self.high_m)} from {other}"

    def form(self) -> dict:
        out = {"filter": self.kind, "negated": self.negated, "of": self.other.form()}
        if self.kind == "rel":
            out["relation"] = self.relation
        else:
            out["within_m"] = [self.low_m, self.high_m]
        return out


@dataclass
class NP:
    """A noun phrase: the words of its noun, a number ("chair 3"), an extreme ("the smallest"),
    and the filters after it ("on the table next to the pink book")."""

    words: list[str]
    number: Optional[int] = None
    superlative: Optional[str] = None       # the word: biggest, smallest, tallest, ...
    toward: Optional["NP"] = None           # "the cup farthest from the tv": the distance's other end
    filters: list[Filter] = field(default_factory=list)
    alternatives: list["NP"] = field(default_factory=list)   # "cups or books"
    definite: bool = False                  # "the ..." (one thing expected)
    indefinite: bool = False                # "a / any ...": every object of the kind, never one by name

    def text(self) -> str:
        return " ".join(self.words + ([str(self.number)] if self.number is not None else []))

    def describe(self) -> str:
        if self.alternatives:
            return " or ".join(a.describe() for a in self.alternatives)
        head = " ".join(x for x in (self.superlative or "", self.text()) if x) or "objects"
        if self.toward is not None:
            head += f" ({self.superlative} from {self.toward.describe()})"
        return " ".join([("the " if self.definite else "") + head] + [f.describe() for f in self.filters])

    def form(self) -> dict:
        if self.alternatives:
            return {"any_of": [a.form() for a in self.alternatives]}
        out: dict = {"noun": self.text() or "objects"}
        if self.superlative:
            out["extreme"] = self.superlative
        if self.toward is not None:
            out["from"] = self.toward.form()
        if self.filters:
            out["filters"] = [f.form() for f in self.filters]
        return out


@dataclass
class Form:
    """The operation on top: count, exists, list, where, attribute, extreme, distance, compare,
    at_least, rooms, room_count, room_most, rooms_next_to, affordance."""

    op: str
    sets: list[NP] = field(default_factory=list)
    attribute: Optional[str] = None         # colour | size | height | tall | width | length
    compare: Optional[str] = None           # more | fewer (compare, at_least, room_most)
    number: Optional[float] = None          # at_least: the N of "more than N"
    filters: list[Filter] = field(default_factory=list)     # predicates after the verb
    verb: Optional[str] = None              # affordance: "sit", "put"

    def form(self) -> dict:
        out: dict = {"op": self.op, "sets": [s.form() for s in self.sets]}
        for k in ("attribute", "compare", "number", "verb"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        if self.filters:
            out["filters"] = [f.form() for f in self.filters]
        return out


def fmt_m(metres: Optional[float]) -> str:
    if metres is None:
        return "?"
    return f"{metres * 100:.0f} cm" if metres < 1 else f"{metres:.2f}".rstrip("0").rstrip(".") + " m"
