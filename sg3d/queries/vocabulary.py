"""The words of questions, written once (sg3d/queries/data/lexicon.toml): relations, colours, sizes,
extremes, units, affordances, scope words, and the examples a refusal offers; and row limits.

The grammar (sg3d/queries/reader/grammar.py) builds its relation rule from `RELATIONS`; the sets
(sg3d/queries/sets.py), the per-form templates (sg3d/queries/vqa.py) and the answers read the
same tables, so a word the grammar reads is a word every answer knows.
"""
from __future__ import annotations

from sg3d.core.model import COLOUR_NAMES
from sg3d.queries.reader.data import lexicon_file

# the words themselves are data (sg3d/queries/data/lexicon.toml); here they get their types
_L = lexicon_file()
# relation words -> (relation type, symmetric?). Types are a fixed whitelist (templates render
# them, sg3d/graphdb/cypher.py); IN_FRONT_OF, BEHIND, LEFT_OF and RIGHT_OF are never stored: they
# are computed from a viewpoint when asked (sg3d/queries/viewpoint.py).
RELATIONS: dict[str, tuple[str, bool]] = {w: (t, sym) for w, (t, sym) in _L["relations"].items()}
# the stored relation types a set filter reads (the viewpoint ones are computed, never read)
STORED_TYPES = ("ON", "IN", "UNDER", "ABOVE", "BELOW", "NEXT_TO", "NEAR")
# A stored pair is either NEXT_TO or NEAR (one statement per pair): "next to" is the closer form
# of "near", so a question about what is near (around, close to) X also means what is next to it.
# Likewise UNDER (covered by the thing above) and BELOW (air between) are the graph's two kinds of
# beneath, and people say "under" and "below" for either: each word asks for both.
IMPLIED_BY: dict[str, tuple[str, ...]] = {"NEAR": ("NEAR", "NEXT_TO"), "UNDER": ("UNDER", "BELOW"),
                                          "BELOW": ("BELOW", "UNDER")}
# Stored edges that say the same read from the other end: "the chair is above the desk" also
# when the graph stores desk -UNDER-> chair (or -BELOW->); "X is under Y" when Y -ABOVE-> X. An
# answer reads a relation both ways, never reversing one (X -ON-> Y is never "Y is on X").
INVERSE: dict[str, tuple[str, ...]] = {"ABOVE": ("UNDER", "BELOW"), "UNDER": ("ABOVE",), "BELOW": ("ABOVE",)}
REL_WORDS: dict[str, str] = _L["relation_said"]

COLOURS: dict[str, str] = {c: c for c in COLOUR_NAMES} | _L["colour_words"]
SIZES: dict[str, str] = _L["sizes"]
SUPERLATIVES: dict[str, tuple[str, int]] = {w: (k, sign) for w, (k, sign) in _L["superlatives"].items()}
DISTANCE_SUPERLATIVES: dict[str, int] = _L["distance_superlatives"]
UNIT_M: dict[str, float] = _L["unit_m"]
ATTRIBUTES: dict[str, str] = _L["attributes"]
NEVER_IGNORED = frozenset(_L["never_ignored"])
STRUCTURE_LABELS: dict[str, str] = _L["structure_labels"]
GENERIC: set[str] = set(_L["generic"])
EVERYWHERE: set[str] = set(_L["everywhere"])
ROOM_WORDS: tuple[str, ...] = tuple(_L["room_words"])
ACTIVITIES: dict[str, list[str]] = _L["activities"]
GERUNDS: dict[str, str] = _L["gerunds"]
AFFORDANCE_VERBS: dict[str, str] = _L["affordance_verbs"]
AFFORDANCE_PARTICLES: set[str] = set(_L["affordance_particles"])
AFFORDANCE_FILLER: set[str] = set(_L["affordance_filler"])
EXTRA_AFFORDANCES: dict[str, list[str]] = _L["extra_affordances"]

MAX_QUESTION = 500     # characters; longer text is refused before any reading
PROVENANCE_MAX = 50    # objects whose provenance an answer carries (a count of more names none)
ROW_LIMIT = 100_000    # rows fetched for listing/size filtering; counts without size use count()
LIST_SHOWN = 12        # objects named in a one-line answer
ABSENT = "small or uncommon things may be missed"

EXAMPLES: list[str] = _L["examples"]


def example_for(question: str) -> str:
    """The example question closest to `question` (shared words first, then spelling)."""
    import difflib
    import re

    def words(text: str) -> set[str]:
        return set(re.sub(r"[^a-z0-9 ]+", " ", text.lower()).split())

    asked = words(question)
    return max(EXAMPLES, key=lambda e: (len(asked & words(e)),
                                        difflib.SequenceMatcher(None, question.lower(), e).ratio()))


def refusal(why: str, question: str) -> str:
    """One short line: what was not understood, and one example close to the question."""
    return f"{why}; try e.g. \"{example_for(question)}\""
