"""The logical form of a question: sets of objects filtered by relations, and one operation.

Plain data the grammar (sg3d/queries/reader/grammar.py) produces and the compiler (sg3d/queries/compose.py)
answers. Words are kept as they were read, so a refusal can name the one it did not understand.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, Optional, get_args

from sg3d.queries.lexicon import Target


@dataclass
class Filter:
    """A restriction of a set by another set: a stored relation, or a distance band."""

    kind: str                               # rel | distance | except
    other: "NP"
    relation: Optional[str] = None          # the relation word ("next to") when kind == rel
    low_m: Optional[float] = None           # distance band, metres (centre to centre)
    high_m: Optional[float] = None
    negated: bool = False
    reverse: bool = False                   # "what is the cup on": the relation's other end

    def describe(self, other: Optional[str] = None) -> str:
        """The filter in words; `other` names the other set (default: its own description)."""
        neg = "not " if self.negated else ""
        other = self.other.describe() if other is None else other
        if self.kind == "rel" and self.reverse:
            return f"that {other} is {neg}{self.relation}"
        if self.kind == "rel":
            return f"{neg}{self.relation} {other}"
        if self.kind == "except":
            return f"except {other}"
        if self.low_m is None:
            return f"{neg}within {fmt_m(self.high_m)} of {other}"
        if self.high_m is None:
            return f"{neg}farther than {fmt_m(self.low_m)} from {other}"
        return f"{neg}between {fmt_m(self.low_m)} and {fmt_m(self.high_m)} from {other}"

    def form(self) -> dict:
        out = {"filter": self.kind, "negated": self.negated, "of": self.other.form()}
        if self.kind == "rel":
            out["relation"] = self.relation
            if self.reverse:
                out["reverse"] = True
        elif self.kind == "distance":
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
    purpose: Optional[str] = None           # "furniture for sitting": the activity's words
    ignored: list[str] = field(default_factory=list)   # "with a white glaze": words no answer uses (said)
    joined: str = "or"                      # alternatives said with "and" ("a chair and a tv") or "or"
    pronoun: Optional[str] = None           # "the grey one(s)": the noun is the one said before

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
        if self.purpose:
            out["for"] = self.purpose
        if self.ignored:
            out["ignored"] = list(self.ignored)
        if self.filters:
            out["filters"] = [f.form() for f in self.filters]
        return out


# the operations a question asks for (sg3d/queries/answer/operations.py OPS answers each; changes, gone and
# before are answered from the scans' history by the application)
Op = Literal["count", "exists", "at_least", "compare", "list", "where", "attribute", "extreme", "distance",
             "rooms", "room_most", "rooms_next_to", "room_count", "affordance", "rooms_counted", "size_compare",
             "size_which", "rooms_next_hold", "route", "changes", "gone", "before"]
OPS: tuple[Op, ...] = get_args(Op)


@dataclass(frozen=True)
class Form:
    """What a question asks, as read: the operation on top (`Op`) over sets of objects. Never
    changed once read (a step that reads it otherwise makes a new one, `dataclasses.replace`)."""

    op: Op
    sets: list[NP] = field(default_factory=list)
    attribute: Optional[str] = None         # colour | size | height | tall | width | length
    compare: Optional[str] = None           # more | fewer (compare, at_least, room_most); exists (affordance asked yes/no)
    number: Optional[float] = None          # at_least: the N of "more than N"
    filters: list[Filter] = field(default_factory=list)     # predicates after the verb
    verb: Optional[str] = None              # affordance: "sit", "put"
    seen_from: Optional[NP] = None          # "as seen from the sink": the eye of a viewpoint relation
    among: list[NP] = field(default_factory=list)   # room_most: only these rooms ("the kitchen or the study")
    lacking: list[NP] = field(default_factory=list)  # rooms: holding none of these ("have no fridge")
    # the one-word stand-ins the reader put for multi-word room names (stand-in -> the name as said)
    rooms_said: dict[str, str] = field(default_factory=dict)

    def form(self) -> dict:
        out: dict = {"op": self.op, "sets": [s.form() for s in self.sets]}
        for k in ("attribute", "compare", "number", "verb"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        if self.filters:
            out["filters"] = [f.form() for f in self.filters]
        if self.seen_from is not None:
            out["seen_from"] = self.seen_from.form()
        if self.among:
            out["among"] = [a.form() for a in self.among]
        if self.lacking:
            out["lacking"] = [a.form() for a in self.lacking]
        return out


def fmt_m(metres: Optional[float]) -> str:
    if metres is None:
        return "?"
    return f"{metres * 100:.0f} cm" if metres < 1 else f"{metres:.2f}".rstrip("0").rstrip(".") + " m"


@dataclass
class Query:
    """The plan of a simple form (one kind of object, at most one relation to another kind, a
    room): what the index-aware per-form templates of sg3d/queries/vqa.py are run with. Made
    from a Form by the planner (sg3d/queries/compose.py, `plan_simple`), never from text."""

    form: str                               # count | exists | list | attribute | show | rooms | where
    target: Target
    colour: Optional[str] = None
    size: Optional[str] = None              # big | small (vs the category's median volume)
    superlative: Optional[str] = None       # max | min | closest (volume, or distance to anchor)
    relation: Optional[str] = None          # a whitelisted relation type
    relation_word: Optional[str] = None
    symmetric: bool = False
    anchor: Optional[Target] = None
    anchor_article: str = "the"             # "next to a cup" (any cup) / "next to the cup"
    room: Optional[str] = None              # a room name from "in the kitchen"
    attribute: Optional[str] = None         # colour | size (attribute lookups)
    anchor_colour: Optional[str] = None     # "next to the red controller"
    one: bool = False                       # "the cup": one object is meant (several: ask which)
    notes: list[str] = field(default_factory=list)
    ignored: list[str] = field(default_factory=list)   # words read but not used (reported)

    def mappings(self) -> list[str]:
        """How the object words were read (synonym, group, embedding, unknown), for --explain."""
        return [m for t in (self.target, self.anchor) if t is not None for m in [t.mapping()] if m]

    def summary(self) -> dict:
        out = {"form": self.form, "target": self.target.describe(), "labels": self.target.labels}
        for k in ("colour", "size", "superlative", "relation", "room", "attribute", "anchor_colour"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        if self.anchor is not None:
            out["anchor"] = self.anchor.describe()
            out["anchor_labels"] = self.anchor.labels
        if self.mappings():
            out["mapping"] = self.mappings()
        if self.ignored:
            out["ignored"] = self.ignored
        return out

    def anchor_target(self) -> Target:
        """The object the relation or distance is to (a relation always has one)."""
        if self.anchor is None:
            raise ValueError("this query has no anchor")
        return self.anchor


@dataclass
class ChangeQuery:
    """A question about what re-scans changed, as the grammar read it: "what changed in the
    kitchen" (changes), "what is gone" (gone), "where was the cup before" (before)."""

    form: str                        # changes | gone | before
    target: Optional[Target] = None  # "before": the objects asked about
    room: Optional[str] = None       # the room the question names, as said
