"""Colours, relation words and the one-line-per-pair edge model shared by every picture."""
from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import lru_cache
from typing import Iterable

from sg3d.core.relation_rules import SYMMETRIC
from sg3d.core.stored import StoredRelation

# matplotlib's tab20, as hex: 20 well-separated colours that plotly draws identically
PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
           "#bcbd22", "#17becf", "#aec7e8", "#ffbb78", "#98df8a", "#ff9896", "#c5b0d5", "#c49c94",
           "#f7b6d2", "#c7c7c7", "#dbdb8d", "#9edae5"]
STATUS_COLOURS = {"matched": "#2eaa46", "spurious": "#dc2828", "duplicate": "#ff9600"}
MISSING_COLOUR = "#c80000"

# Size statements connect nearly every pair and bury the spatial ones: hidden unless asked for.
COMPARISON_TYPES = frozenset({"BIGGER_THAN", "SMALLER_THAN"})
# One colour per stored relation type (lines and legend of the 3-D view): the Okabe-Ito
# colour-blind-safe set for the spatial ones, greys for the size statements (drawn dotted).
RELATION_COLOURS = {"ON": "#d55e00", "IN": "#cc79a7", "UNDER": "#e69f00", "ABOVE": "#0072b2",
                    "BELOW": "#000000", "NEXT_TO": "#009e73", "NEAR": "#56b4e9",
                    "BIGGER_THAN": "#8c8c8c", "SMALLER_THAN": "#5a5a5a"}
# The word for "b TYPE a" said from a's side: an edge drawn against its stored direction reads so.
INVERSE_WORDS = {"ON": "holds", "IN": "contains", "ABOVE": "below", "BELOW": "above", "UNDER": "over",
                 "BIGGER_THAN": "smaller than", "SMALLER_THAN": "bigger than", "IN_FRONT_OF": "behind",
                 "BEHIND": "in front of", "LEFT_OF": "right of", "RIGHT_OF": "left of"}
# Which statement of a pair sets the arrow's direction: support first, size last.
PRIORITY = ("ON", "IN", "UNDER", "ABOVE", "BELOW", "NEXT_TO", "NEAR", "IN_FRONT_OF", "BEHIND",
            "LEFT_OF", "RIGHT_OF", "BIGGER_THAN", "SMALLER_THAN")


def word(rel_type: str) -> str:
    """ON -> "on", NEXT_TO -> "next to"."""
    return rel_type.lower().replace("_", " ")


@lru_cache(maxsize=1)
def _groups() -> tuple[str, ...]:
    from sg3d.queries.taxonomy import Taxonomy

    return tuple(sorted(Taxonomy.load().groups))


def category_of(label: str) -> str:
    """The label's taxonomy group (its parent), or the label itself outside the taxonomy."""
    from sg3d.queries.taxonomy import Taxonomy

    return Taxonomy.load().parent(label) or label


def category_colour(group: str) -> str:
    """One colour per taxonomy group, the same in every picture (its index among the fixed
    taxonomy's groups, not among what a room holds); other names by a stable hash."""
    groups = _groups()
    if group in groups:
        return PALETTE[groups.index(group) % len(PALETTE)]
    return PALETTE[int(hashlib.sha1(group.encode()).hexdigest(), 16) % len(PALETTE)]


def relation_colour(rel_type: str) -> str:
    """The colour of a relation type's lines; a type outside RELATION_COLOURS by a stable hash."""
    if rel_type in RELATION_COLOURS:
        return RELATION_COLOURS[rel_type]
    return PALETTE[int(hashlib.sha1(rel_type.encode()).hexdigest(), 16) % len(PALETTE)]


def visible_edges(edges: Iterable[StoredRelation], all_edges: bool) -> list[StoredRelation]:
    return [e for e in edges if all_edges or e.type not in COMPARISON_TYPES]


@dataclass
class PairEdge:
    """Every statement between two objects, as one line: s -> o, read "s <words> o"."""
    s: str
    o: str
    words: list[str]
    types: list[str]          # stored types behind the words
    directed: bool            # False when every statement is symmetric (NEXT_TO, NEAR)
    comparison: bool          # only size statements

    @property
    def label(self) -> str:
        return " / ".join(self.words)


def pair_edges(edges: Iterable[StoredRelation]) -> list[PairEdge]:
    """One PairEdge per unordered pair, its statements merged into one label ("on / smaller
    than"): the direction is that of the pair's leading statement (PRIORITY), and a statement
    the other way round is said with its inverse word (table BIGGER_THAN cup, read from the cup:
    "smaller than"), so "b BEHIND a" beside "a IN_FRONT_OF b" gives one word, not two labels
    printed over each other."""
    rank = {t: i for i, t in enumerate(PRIORITY)}
    pairs: dict[tuple[str, ...], list[StoredRelation]] = {}
    for e in edges:
        if e.s != e.o:
            pairs.setdefault(tuple(sorted((e.s, e.o))), []).append(e)
    out = []
    for key in sorted(pairs):
        facts = sorted(pairs[key], key=lambda e: (rank.get(e.type, len(rank)), e.s))
        lead = next((e for e in facts if e.type not in SYMMETRIC), facts[0])
        s, o = lead.s, lead.o
        words: list[str] = []
        for e in facts:
            w = word(e.type) if (e.s == s or e.type in SYMMETRIC) else \
                INVERSE_WORDS.get(e.type, word(e.type) + " (reverse)")
            if w not in words:
                words.append(w)
        types = sorted({e.type for e in facts})
        out.append(PairEdge(s, o, words, types, any(t not in SYMMETRIC for t in types),
                            all(t in COMPARISON_TYPES for t in types)))
    return out
