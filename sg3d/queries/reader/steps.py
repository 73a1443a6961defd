"""The rewrites of the rule table (sg3d/queries/data/rephrase_rules.toml) that need more than one
substitution: each a step the table names (`call = "..."`), with its why and examples there.
"""
from __future__ import annotations

import re
import unicodedata
from typing import Callable

from sg3d.queries.reader.data import dictionary, pattern


def fold(text: str) -> str:
    """Lower case, curly quotes straightened, accents kept (room names like 'küche')."""
    text = unicodedata.normalize("NFC", text).lower()
    return text.replace("\u2019", "'").replace("\u2018", "'").replace("\u00d7", " x ")


_DISLOCATED = re.compile(r"^(.+?) (what color|what size|how big|how tall|how high|how wide|how long|how deep|where)"
                         r"(?: (is|are) (?:it|they|that)| (?:it|they|that) (is|are)| (is|are))?(?: at)?$")
_VERBAL = re.compile(r"\b(?:is|are|was|were|can|could|do|does|did|i|you|we|have|has|there|what|which|how|where)\b")


def dislocated(text: str) -> str:
    """"the smallest chair, what colour is it", "the cabinet, where it is?", "the telly - how big?":
    a noun phrase said first, then the question about it (its verb and pronoun in any order, or
    none): the phrase goes where the pronoun stands. Only when what comes first is a noun phrase
    (no verb, no question word of its own)."""
    m = _DISLOCATED.match(text)
    if not m or _VERBAL.search(m.group(1)):
        return text
    verb = m.group(3) or m.group(4) or m.group(5) or "is"
    return f"{m.group(2)} {verb} {m.group(1)}"


NEEDS = dictionary("needs")
_NEED = re.compile(r"^(?:i am|im|i feel|i m) (?:so |very |really |a bit |quite |pretty |kind of |kinda |super )?(" + "|".join(NEEDS)
                   + r")\b(?: (?:and|so|now))?\s*(.*)$")
_NEED_ALONE = re.compile(r"^(?:|where|where to|what now|help|help me|any ideas?|suggestions?|what should i do|"
                         r"what can i do|what do you suggest|what do you recommend|anything|somewhere|any place)$")


def needs(text: str) -> str:
    """"i am thirsty" alone (or with "where?", "any ideas?") asks where the asker can do what the
    need calls for (NEEDS: thirsty -> drink from); followed by a question, the question says it."""
    m = _NEED.match(text)
    if not m:
        return text
    rest = m.group(2).strip()
    return f"where can i {NEEDS[m.group(1)]}" if _NEED_ALONE.match(rest) else rest



_WANT_TO = re.compile(r"^i (?:want|need|have|would like|wish|am going|would love|got) to (.+?)"
                      r"(?: (?:where|somewhere|anywhere|where can i do that|where can i|where to))?$")


def wanting(text: str) -> str:
    """"i want to sit (down) (where)", "i have to put my cup down somewhere": "where can i ...",
    when the verb is one the affordance table knows (vocabulary.AFFORDANCE_VERBS)."""
    from sg3d.queries.vocabulary import AFFORDANCE_VERBS, EXTRA_AFFORDANCES

    m = _WANT_TO.match(text)
    if not m:
        return text
    verb = m.group(1).split()[0]
    known = {k.split()[0] for k in list(AFFORDANCE_VERBS) + list(EXTRA_AFFORDANCES)}
    return f"where can i {m.group(1)}" if verb in known else text


_CONTEXT = re.compile(r"^(?:(?:ok|okay|so|hey|well|right|hmm|um|oh)[ ,]+)*(?:i|i'm|im|i've|i'd|we|we're|my|our|me)\b"
                      r"[^?]*?(?: [-\u2013\u2014]+ ?|[-\u2013\u2014]{2} ?| ?[,;:] ?|\. )"
                      r"((?:is|are|where|what|which|how|do|does|can|could|any|anything|something|anywhere|somewhere|have|has|got|"
                      r"would|will)\b.+)$")
_DO_THAT = re.compile(r"\b(?:do|doing) (?:that|it|so|this)\b|\bthere\s*\??$")


def context_clause(text: str) -> str:
    """The question of "<a statement about me>, <a question>" (split at a dash, comma, semicolon,
    colon or full stop): the statement says why, the question what. Kept whole when the question
    leans on the statement ("... - where can I do that?") or is a bare "where?" / "any ideas?"
    (`needs` reads those). A pronoun of the question ("I can't find the purple book. Where is
    it?") is the statement's last noun phrase (`antecedent`)."""
    m = _CONTEXT.match(text) or (None if pattern("tag-question").search(text) else _STATED.match(text))
    if not m:
        return text
    rest = m.group(1).strip()
    plain = " ".join(re.sub(r"[^\w' ]+", " ", rest).split())
    if len(plain.split()) < 2 or _NEED_ALONE.match(plain) or _DO_THAT.search(rest):
        return text
    rest = pattern("activity-pronoun").sub(r"\1", rest)
    purpose = need_for_it(text[:m.start(1)], rest)
    if purpose is not None:
        return purpose
    if _PRONOUN.search(rest) and not pattern("tag-question").search(text):
        said = antecedent(text[:m.start(1)])
        return _PRONOUN.sub(said, rest) if said else text
    return rest if m.re is _CONTEXT else text


# "I need to put my shopping down. Is there a counter or a table for it?": the statement's activity
# is what "for it" asks for
_NEED_TO = re.compile(r"^(?:(?:ok|okay|so|hey|well|right|hmm|um|oh)[ ,]+)*(?:i|we) (?:need|want|have|would like|wish|"
                      r"am going|are going|got|d like|must|am trying|are trying) to ([\w' -]+?)[\s,.;:!?\u2013\u2014-]*$")
_FOR_IT = re.compile(r"^((?:is|are) there .+?) (?:for|to do) (?:it|them|that|this|so)\s*[?.!]*\s*$")


def need_for_it(statement: str, question: str) -> str | None:
    """"I need to put my shopping down. Is there a counter or a table for it?": "is there a
    counter or a table I could put my shopping down" (the activity asked of those kinds), when
    the statement wants an activity the affordance table knows; None otherwise."""
    from sg3d.queries.vocabulary import AFFORDANCE_VERBS, EXTRA_AFFORDANCES

    said, asked = _NEED_TO.match(statement.strip()), _FOR_IT.match(question.strip())
    if not said or not asked:
        return None
    doing = said.group(1).strip()
    if doing.split()[0] not in {k.split()[0] for k in list(AFFORDANCE_VERBS) + list(EXTRA_AFFORDANCES)}:
        return None
    return f"{asked.group(1)} i could {doing}"


# "there's a purple book somewhere, where is it?", "the grey mug is missing - where is it?": a
# statement about a thing (not the asker), then a question with a pronoun for it
_STATED = re.compile(r"^(?:(?:ok|okay|so|hey|well|right|hmm|um|oh)[ ,]+)*(?:there(?:'s| is| are| was| were)\b|"
                     r"(?:the|my|our|a|an|some)\b[^?]*?\b(?:is|are|was|were|has|have|had|'s|went|got|seems?)\b)[^?]*?"
                     r"(?: [-\u2013\u2014]+ ?|[-\u2013\u2014]{2} ?| ?[,;:] ?|\. )"
                     r"((?:is|are|where|what|which|how|do|does|can|could|any|anything|something|anywhere|somewhere|have|has|got|"
                      r"would|will)\b.+)$")
# the pronouns a question uses for a thing said before it
_PRONOUN = re.compile(r"\b(?:it|them|they)\b")
_NP_AFTER = re.compile(r"\b(the|a|an|my|our|your|some|this|that|these|those)\s+([\w'-]+(?:\s+[\w'-]+){0,3})")
# words that end a noun phrase (a preposition, an adverb, a verb): "the cup somewhere", "my keys again"
_NP_END = frozenset({
    "somewhere", "anywhere", "here", "there", "again", "now", "today", "yesterday", "earlier", "before", "down",
    "away", "back", "up", "off", "out", "in", "on", "at", "to", "from", "with", "into", "onto", "under", "near",
    "by", "next", "for", "of", "and", "but", "so", "or", "is", "are", "was", "were", "has", "have", "had", "it",
    "them", "i", "we", "you", "last", "this", "that", "anymore", "too", "either", "please", "around", "about",
    "lately", "recently", "just", "still", "can", "cannot", "can't", "seems", "seem", "went", "got",
    "missing", "gone", "lost",
})


def antecedent(statement: str) -> str | None:
    """The last noun phrase of `statement` ("i can't find the purple book" -> "the purple book",
    "i lost my keys again" -> "my keys"), said definite ("a mug" -> "the mug"); None when it names
    none."""
    found = None
    for m in _NP_AFTER.finditer(re.sub(r"[^\w' -]+", " ", statement)):
        words = []
        for w in m.group(2).split():
            if w in _NP_END:
                break
            words.append(w)
        if words:
            det = "the" if m.group(1) in ("a", "an", "some", "this", "that") else m.group(1)
            found = f"{det} {' '.join(words)}"
    return found



_NUMBER_OR_BOTH = r"(?:\d+|both|both of the|both the|all|all of the|all the)"
# "where are the two books", "what colour are both chairs": all of them, the number aside
_THE_N = re.compile(r"^((?:where|what color|what size|how (?:big|tall|high|wide|long|deep)) (?:is|are) )"
                    r"(?:the (\d+)|(both|both of the|both the)) (?=[a-z])")


def the_n(text: str) -> tuple[str, list[str]]:
    """"where are the two books", "what colour are both chairs": the question is about every one
    of them; the number is said back as read ("read 'the 2 books' as 'the books'")."""
    m = _THE_N.match(text)
    if not m:
        return text, []
    said = f"the {m.group(2)}" if m.group(2) else m.group(3)
    rest = text[m.end():]
    return f"{m.group(1)}the {rest}", [f"read '{said} {rest}' as 'the {rest}' (every one)"]



_IS_IT_TRUE = re.compile(r"^(?:is it|it is|is that|its|is this) (?:true|correct|right|the case|so) (?:that )?")


def is_it_true(text: str) -> str:
    """"is it true (that) S": S asked ("there is X" -> "is there X", "the kitchen has X" ->
    "does the kitchen have X", "the cup is on X" -> "is the cup on X")."""
    m = _IS_IT_TRUE.match(text)
    return asked(text[m.end():]) if m else text


# "this room has no books", "the kitchen doesn't have a sink", "the cup is on the table": a
# statement (said with "?" or a tag) asked as a question, when it holds no question word
_STATEMENT = re.compile(r"^(?:the|this|that|these|those|my|our|your) (?:(?!has\b|have\b|is\b|are\b|does\b|do\b)[\w-]+ ?)"
                        r"{1,6} (?:has|have|is|are|does not have|do not have)\b")
_QUESTION_WORD = re.compile(r"\b(?:what|where|which|how|who|whose|when|why|whether)\b")


def statement(text: str) -> str:
    """A statement whose subject is a noun phrase ("this room has no books", "the chairs are
    near the table", "the kitchen does not have a fridge") as its yes/no question (`asked`)."""
    if not _STATEMENT.match(text) or _QUESTION_WORD.search(text):
        return text
    return asked(text)


def asked(rest: str) -> str:
    """A statement as its yes/no question: "there is X" -> "is there X", "the kitchen has X" ->
    "does the kitchen have X", "the kitchen does not have X" -> "does the kitchen not have X",
    "the cup is on X" -> "is the cup on X"."""
    rest = re.sub(r"^there (is|are)\b", r"\1 there", rest)
    rest = re.sub(r"^((?:the|a|an|my|our|this|your|that|these|those) (?:(?!has\b|have\b|is\b|are\b|does\b|do\b)[\w-]+ ?)"
                  r"{1,3}) (does|do) not have\b", r"\2 \1 not have", rest)
    rest = re.sub(r"^((?:the|a|an|my|our|this|your|that|these|those) (?:(?!has\b|have\b|is\b|are\b)[\w-]+ ?){1,6}) "
                  r"(has|have)\b", lambda m: f"{'does' if m.group(2) == 'has' else 'do'} {m.group(1)} have", rest)
    rest = re.sub(r"^((?:the|a|an|my|our|this|your|that|these|those) (?:(?!has\b|have\b|is\b|are\b)[\w-]+ ?){1,6}) "
                  r"(is|are)\b", r"\2 \1", rest)
    return " ".join(rest.split())


_EMBEDDED = re.compile(r"^(what color|what size|where|what|which|how many \w+(?: \w+)?|how far|how tall|how high|how big) "
                       r"(the [\w\s-]+?|[\w\s-]+?) (is|are)$")
_EMBEDDED_THERE = re.compile(r"^how many (.+?) there (?:is|are)\b(.*)$")
def reorder_embedded(text: str) -> str:
    """'where the sink is' -> 'where is the sink' (what is left of 'can you tell me where ...')."""
    m = _EMBEDDED_THERE.match(text)
    if m:
        return f"how many {m.group(1)} are there{m.group(2)}"
    m = _EMBEDDED.match(text)
    # "how many white things are": already in question order (an embedded count names its room:
    # "how many chairs the kitchen is" is no English)
    if m and m.group(1).startswith("how many") and not m.group(2).startswith("the "):
        return text
    if m and not re.search(r"\b(is|are)\b", m.group(2)):
        return f"{m.group(1)} {m.group(3)} {m.group(2)}"
    return text


_POLITE_TAIL = re.compile(r"[\s,]*\b(?:please|pls|plz|thanks|thank you|thx|cheers|kindly)\s*[?.!]*\s*$")


def polite_tail(text: str) -> str:
    """"tell me the colour of the living room's chair please": the trailing "please" (thanks,
    kindly) goes before possessives are read, so it is never taken for part of a noun; the
    question's own "?" stays."""
    m = _POLITE_TAIL.search(text)
    if not m or not text[:m.start()].strip():
        return text
    return text[:m.start()] + ("?" if "?" in m.group(0) else "")


# "is there a bin somewhere in this kitchen", "a cup anywhere on the table": "somewhere" before a


def asides(text: str) -> tuple[str, list[str]]:
    """Asides in brackets ("(the big one)", "[sic]"), innermost first: gone, and returned."""
    dropped: list[str] = []
    while True:
        found = re.findall(r"\([^()]*\)|\[[^\[\]]*\]", text)
        if not found:
            return text, dropped
        dropped += [f.strip() for f in found]
        text = re.sub(r"\([^()]*\)|\[[^\[\]]*\]", " ", text)


def squash(text: str) -> str:
    return " ".join(text.split())


def _plus(n: int) -> Callable[[re.Match[str]], str]:
    """"no more than 3" = "fewer than 4", "3 or more" = "more than 2": the bound moved by `n`."""
    def said(m: re.Match[str]) -> str:
        word = "fewer" if n > 0 else "more"
        return f"{word} than {int(m.group(1)) + n}"
    return said


def _at_least_most(m: re.Match[str]) -> str:
    """"at least 2" = "more than 1", "at most 2" = "fewer than 3" (whole numbers)."""
    return f"more than {int(m.group(2)) - 1}" if m.group(1) == "least" else f"fewer than {int(m.group(2)) + 1}"


def _does_have(m: re.Match[str]) -> str:
    return f"how many {m.group(1)} {'does' if m.group(2) == 'has' else 'do'} {m.group(3)} have"


def _self_relation_has(m: re.Match[str]) -> str:
    return f"{m.group(1)} {m.group(2)} {'is' if m.group(3) == 'has' else 'are'} {m.group(6)} {m.group(4) or ''}{m.group(5)}"


UNITS = dictionary("units")
GERUNDS = dictionary("gerunds")
REPLACERS: dict[str, Callable[[re.Match[str]], str]] = {
    "lie_down": lambda m: "lie down" if m.group(1) in ("lie down", "lie-down") else m.group(1),
    "unit_between": lambda m: f"how many {UNITS[m.group(1)]} between",
    "unit": lambda m: f"{m.group(1)} {UNITS[m.group(2)]}",
    "does_have": _does_have,
    "self_relation_has": _self_relation_has,
    "self_relation_with": lambda m: f"{m.group(1)} {m.group(4)} {m.group(2) or ''}{m.group(3)}",
    "fewer_than_next": _plus(1),
    "more_than_previous": _plus(-1),
    "more_than_same": lambda m: f"more than {m.group(1)}",
    "fewer_than_same": lambda m: f"fewer than {m.group(1)}",
    "at_least_most": _at_least_most,
    "gerund": lambda m: GERUNDS[m.group(1)],
}


def _typo_steps() -> dict[str, Callable]:
    from sg3d.queries.reader.typos import first_word_typo, were_for_where

    return {"first_word_typo": first_word_typo, "were_for_where": were_for_where}


STEPS: dict[str, Callable] = {
    "fold": fold, "context_clause": context_clause, "polite_tail": polite_tail, "asides": asides, "squash": squash,
    "needs": needs, "wanting": wanting, "dislocated": dislocated, "reorder_embedded": reorder_embedded,
    "the_n": the_n, "statement": statement, "is_it_true": is_it_true, **_typo_steps(),
}
