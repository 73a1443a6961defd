"""Which stored relations may hold together for one pair of objects, and how each is stored.

Every stored edge states one *statement* about an unordered pair {lo, hi} (lo = the smaller id).
Statements come in two families; within a family a pair holds at most ONE statement:

- placement (where one is relative to the other, viewpoint-invariant), two sides and a middle:
  "lo is over/in hi": lo IN hi, lo ON hi, lo ABOVE hi (stored with hi BELOW lo), hi UNDER lo;
  "hi is over/in lo": the mirror four;
  "side by side": lo NEXT_TO hi, lo NEAR hi.
  A cup is on the table, or above it, or next to it: never two of these.
- size: lo BIGGER_THAN hi (stored with hi SMALLER_THAN lo), or the mirror.

Storage forms (what ingest emits and the store keeps):
- symmetric relations (NEXT_TO, NEAR) are ONE edge whose subject is the smaller id, read both
  ways by every query;
- inverse pairs (ABOVE/BELOW, BIGGER_THAN/SMALLER_THAN) are stored as both edges, so a query
  follows one edge type;
- CONTAINS_OBJ is IN read backwards: it never reaches the store from ingest;
- viewpoint relations (IN_FRONT_OF, BEHIND, LEFT_OF, RIGHT_OF) depend on where the observer
  stands: they are never stored (computed at query time from a stated viewpoint).

A statement is `(family, lo, hi, form)`; `form` is a tag read from lo to hi: "ON" = lo ON hi,
"~ON" = hi ON lo. Tags are also how `cypher/check_contradictions.cypher` names a pair's edges.
"""
from __future__ import annotations

from itertools import combinations
from typing import NamedTuple, Optional

from sg3d.core.model import RelationObservation

# Relation types whose meaning does not depend on the direction of the edge.
SYMMETRIC = frozenset({"NEXT_TO", "NEAR"})
# a -P-> b says the same as b -INVERSE[P]-> a.
INVERSE = {"ABOVE": "BELOW", "BELOW": "ABOVE", "IN": "CONTAINS_OBJ", "CONTAINS_OBJ": "IN",
           "IN_FRONT_OF": "BEHIND", "BEHIND": "IN_FRONT_OF", "LEFT_OF": "RIGHT_OF",
           "RIGHT_OF": "LEFT_OF", "BIGGER_THAN": "SMALLER_THAN", "SMALLER_THAN": "BIGGER_THAN"}
VIEWPOINT = frozenset({"IN_FRONT_OF", "BEHIND", "LEFT_OF", "RIGHT_OF"})
# Types ingest stores (the whitelist keeps the viewpoint ones for query-time use only).
STORED = ("ON", "UNDER", "ABOVE", "BELOW", "IN", "NEXT_TO", "NEAR", "BIGGER_THAN", "SMALLER_THAN")

PLACEMENT, SIZE = "placement", "size"
# side of a placement form: +1 lo over/in hi, -1 hi over/in lo, 0 side by side
_SIDE = {"IN": 1, "ON": 1, "ABOVE": 1, "~UNDER": 1,
         "~IN": -1, "~ON": -1, "~ABOVE": -1, "UNDER": -1,
         "NEXT_TO": 0, "NEAR": 0,
         "BIGGER": 1, "~BIGGER": -1}
# ties inside a side go to the more specific form
SPECIFICITY = ("IN", "ON", "UNDER", "ABOVE", "NEXT_TO", "NEAR", "BIGGER")


class Statement(NamedTuple):
    family: str
    lo: str
    hi: str
    form: str

    @property
    def side(self) -> int:
        return _SIDE[self.form]

    @property
    def rank(self) -> int:
        return SPECIFICITY.index(self.form.lstrip("~"))


def _flip(form: str) -> str:
    return form[1:] if form.startswith("~") else "~" + form


def statement_of(subject: str, predicate: str, obj: str) -> Optional[Statement]:
    """The statement one edge makes; None for viewpoint relations (never stored)."""
    if predicate in VIEWPOINT or subject == obj:
        return None
    if predicate == "CONTAINS_OBJ":
        subject, predicate, obj = obj, "IN", subject
    elif predicate == "BELOW":
        subject, predicate, obj = obj, "ABOVE", subject
    elif predicate == "SMALLER_THAN":
        subject, predicate, obj = obj, "BIGGER", subject
    elif predicate == "BIGGER_THAN":
        predicate = "BIGGER"
    family = SIZE if predicate == "BIGGER" else PLACEMENT
    if predicate in SYMMETRIC:
        lo, hi = sorted((subject, obj))
        return Statement(family, lo, hi, predicate)
    if subject < obj:
        return Statement(family, subject, obj, predicate)
    return Statement(family, obj, subject, _flip(predicate))


def edges_of(st: Statement, score: float) -> list[RelationObservation]:
    """The stored edges of a statement (see the module docstring)."""
    upper, lower = (st.lo, st.hi) if not st.form.startswith("~") else (st.hi, st.lo)
    base = st.form.lstrip("~")
    if base == "ABOVE":
        return [RelationObservation(upper, "ABOVE", lower, score), RelationObservation(lower, "BELOW", upper, score)]
    if base == "BIGGER":
        return [RelationObservation(upper, "BIGGER_THAN", lower, score),
                RelationObservation(lower, "SMALLER_THAN", upper, score)]
    return [RelationObservation(upper, base, lower, score)]


def tag(subject: str, predicate: str, obj: str) -> str:
    """An edge's name inside its pair: the type read from the smaller id, '~' when backwards."""
    return predicate if subject < obj else "~" + predicate


def _tag_statement(t: str) -> Optional[tuple[str, str]]:
    """(family, form) of a tag, with lo = 'a' < hi = 'b'."""
    p = t.lstrip("~")
    st = statement_of("b", p, "a") if t.startswith("~") else statement_of("a", p, "b")
    return None if st is None else (st.family, st.form)


def exclusive_tag_pairs() -> list[str]:
    """Every pair of edge tags that cannot both hold for one pair of objects, as "X|Y": two
    statements of one family, or a symmetric relation stored both ways (clutter)."""
    tags = [t for p in STORED + ("CONTAINS_OBJ",) for t in (p, "~" + p)]
    out = []
    for x, y in combinations(tags, 2):
        sx, sy = _tag_statement(x), _tag_statement(y)
        assert sx is not None and sy is not None       # every stored type has a statement
        if sx[0] == sy[0] and (sx[1] != sy[1] or x.lstrip("~") in SYMMETRIC):
            out.append(f"{x}|{y}")
    return out


def non_canonical_tags() -> list[str]:
    """Tags of symmetric edges stored against the canonical direction (subject = larger id)."""
    return sorted("~" + p for p in SYMMETRIC)
