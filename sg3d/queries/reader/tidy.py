"""People's phrasing -> the plain text the grammar reads: the rule table run in its order.

Every rewrite that changes a word is reported (the notes of the typo steps and `fix_typos`, the
asides in `Phrased.dropped`), so an answer can say how it read the question ("read 'chiars' as
'chairs'").
"""
from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from typing import Optional

from sg3d.queries.reader.data import dictionary
from sg3d.queries.reader.rules import run_stage, table
from sg3d.queries.reader.steps import fold


@dataclass
class Phrased:
    text: str
    dropped: list[str] = field(default_factory=list)    # asides not used ("(the big one)")
    notes: list[str] = field(default_factory=list)      # words read as others ("read 'whre' as 'where'")


def tidy(question: str) -> Phrased:
    """Question -> normalised words (no typo fixing of the nouns yet): the rule table's stages
    in its order. A function of the text alone (no store, no room names): the last questions'
    results are kept (`_tidied`), a fresh copy for each caller."""
    kept = _tidied(question)
    return Phrased(kept.text, dropped=list(kept.dropped), notes=list(kept.notes))


def traced(question: str, trace: Optional[list] = None) -> Phrased:
    """`question` through every stage of the table; `trace` collects (rule, before, after) for
    each rule that changed the text."""
    text, dropped, notes = question, [], []
    for stage in table().order:
        text, said = run_stage(stage, text, trace)
        if any(r.yields == "dropped" for r in table().stage(stage)):
            dropped += said
        else:
            notes += said
    return Phrased(text, dropped=dropped, notes=notes)


@functools.lru_cache(maxsize=1024)
def _tidied(question: str) -> Phrased:
    return traced(question)


_UNIT_WORDS = r"(m|cm|mm|ft|inch|inches|metres|meters|centimetres|centimeters|millimetres|millimeters|feet|foot)"
_ASKED_UNIT = [re.compile(r"^how many " + _UNIT_WORDS + r" (?:away )?(?:is|are|between)\b"),
               re.compile(r"\bhow far\b.* in " + _UNIT_WORDS + r"$")]


def asked_unit(text: str) -> str | None:
    """The unit a distance is asked in ("how far ... in centimetres", "how many metres is ..."),
    as a key of vocabulary.UNIT_M; None when none is named."""
    said = " ".join(re.sub(r"[^\w' ]+", " ", run_stage("contractions", fold(text))[0]).split())
    said = run_stage("frames", said)[0]
    for regex in _ASKED_UNIT:
        m = regex.search(said)
        if m:
            return dictionary("units").get(m.group(1))
    return None
def said_word(question: str, text: str, word: str) -> str:
    """The words of `question` (as the user typed them) that `word` of the rewritten `text` came
    from: itself where the user typed it, else the span a rewrite or a typo fix put in its place
    ("except" <- "apart from", "what" <- "waht", "is" <- "what's")."""
    import difflib

    said = [w.strip(".'") for w in re.sub(r"[^\w'. -]+", " ", fold(question)).split()]
    said = [w for w in said if w]
    if word in said:
        return word
    words = text.split()
    if word not in words:
        return word
    at = words.index(word)
    shown = [w.lower() for w in said]
    # each typed word as the rewrite reads it alone (contractions undone, numbers as digits)
    parts: list[str] = []
    origin: list[int] = []
    for i, w in enumerate(shown):
        for p in run_stage("numbers", run_stage("contractions", w)[0])[0].split() or [w]:
            parts.append(p)
            origin.append(i)
    for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(a=parts, b=words, autojunk=False).get_opcodes():
        if j1 <= at < j2 and tag != "equal" and i2 > i1:
            typed = sorted({origin[i] for i in range(i1, i2)})
            return " ".join(said[i] for i in range(typed[0], typed[-1] + 1))
        if j1 <= at < j2 and tag == "equal":
            return said[origin[i1 + at - j1]]
    return word
