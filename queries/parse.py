"""Question text -> query form, by rules (no LLM): frame regexes, then the noun phrases.

The parser only produces plain data (`Query`); words never reach Cypher except as parameters,
and relation words map to whitelisted relation types through the fixed `RELATIONS` table.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Callable, Optional

from ingest.model import COLOUR_NAMES
from queries.lexicon import Target, resolve

# relation phrase -> (relation type, symmetric?); longest phrases are tried first
RELATIONS: dict[str, tuple[str, bool]] = {
    "on top of": ("ON", False), "on": ("ON", False), "sitting on": ("ON", False),
    "under": ("UNDER", False), "underneath": ("UNDER", False), "beneath": ("UNDER", False),
    "below": ("BELOW", False), "above": ("ABOVE", False), "over": ("ABOVE", False),
    "inside": ("IN", False), "in": ("IN", False), "within": ("IN", False),
    "next to": ("NEXT_TO", True), "beside": ("NEXT_TO", True), "by": ("NEXT_TO", True),
    "near": ("NEAR", True), "close to": ("NEAR", True), "around": ("NEAR", True),
    "in front of": ("IN_FRONT_OF", False), "behind": ("BEHIND", False),
    "left of": ("LEFT_OF", False), "to the left of": ("LEFT_OF", False),
    "right of": ("RIGHT_OF", False), "to the right of": ("RIGHT_OF", False),
    "bigger than": ("BIGGER_THAN", False), "larger than": ("BIGGER_THAN", False),
    "smaller than": ("SMALLER_THAN", False),
}
_REL_RE = re.compile(r"\b(" + "|".join(sorted(map(re.escape, RELATIONS), key=len, reverse=True)) + r")\b")

COLOURS = {c: c for c in COLOUR_NAMES} | {"gray": "grey", "silver": "grey", "golden": "yellow"}
SIZES = {"big": "big", "large": "big", "huge": "big", "small": "small", "little": "small", "tiny": "small"}
SUPERLATIVES = {"biggest": "max", "largest": "max", "smallest": "min", "tiniest": "min"}
CLOSEST = re.compile(r"\b(?:closest|nearest)(?: to)?\b")
# words that carry no meaning for the query
FILLER = {"the", "a", "an", "any", "some", "all", "of", "there", "are", "is", "do", "does", "you",
          "we", "i", "see", "can", "have", "has", "here", "total", "altogether", "in", "one", "ones",
          "that", "which", "currently", "please", "many", "me"}
PIECES = re.compile(r"\b(?:pieces?|kinds?|types?|sorts?|bits?) of\b")
EVERYWHERE = re.compile(r"\b(?:in|on) (?:the |this |my )?(?:environment|scene|house|home|world|map|building|whole \w+|total)\b")


class ParseError(ValueError):
    """The question is outside what the rules understand; the message says why."""


@dataclass
class Query:
    form: str                               # count | exists | list | attribute | show | rooms | where
    target: Target
    colour: Optional[str] = None
    size: Optional[str] = None              # big | small (vs the category's median volume)
    superlative: Optional[str] = None       # max | min | closest (volume, or distance to anchor)
    relation: Optional[str] = None          # a whitelisted relation type
    relation_word: Optional[str] = None
    symmetric: bool = False
    anchor: Optional[Target] = None
    room: Optional[str] = None              # a room name from "in the kitchen"
    attribute: Optional[str] = None         # colour | size (attribute lookups)
    notes: list[str] = field(default_factory=list)

    def summary(self) -> dict:
        out = {"form": self.form, "target": self.target.describe(), "labels": self.target.labels}
        for k in ("colour", "size", "superlative", "relation", "room", "attribute"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        if self.anchor is not None:
            out["anchor"] = self.anchor.describe()
            out["anchor_labels"] = self.anchor.labels
        return out


PARENTHETICAL = re.compile(r"\([^()]*\)|\[[^\[\]]*\]")


def normalise(text: str) -> str:
    # parenthetical remarks "( ... )" are asides, not part of the question (innermost first)
    while True:
        stripped = PARENTHETICAL.sub(" ", text)
        if stripped == text:
            break
        text = stripped
    # "A / B" and "A and/or B" name alternatives: read as "A or B"
    text = re.sub(r"\band\s*/\s*or\b", " or ", text, flags=re.I)
    text = re.sub(r"\s*/\s*", " or ", text)
    text = text.lower().replace("colour", "color").replace("’", "'")
    text = re.sub(r"[^a-z0-9' ]+", " ", text)
    return " ".join(text.split())


# (regex, form, attribute) — the question frames, tried in order
FRAMES: list[tuple[re.Pattern, str, Optional[str]]] = [
    # which rooms hold an object (issue 7): before "what/which ... is" and "is there"
    (re.compile(r"^(?:which|what) rooms? (?:has|have|holds?|contains?) (?P<rest>.+)$"), "rooms", None),
    (re.compile(r"^in (?:which|what) rooms? (?:is|are) (?:there )?(?P<rest>.+)$"), "rooms", None),
    (re.compile(r"^how many (?P<rest>.+)$"), "count", None),
    (re.compile(r"^what(?: is the)? number of (?P<rest>.+)$"), "count", None),
    (re.compile(r"^count (?:the )?(?P<rest>.+)$"), "count", None),
    (re.compile(r"^(?:is|are) there (?P<rest>.+)$"), "exists", None),
    (re.compile(r"^(?:do|does|can) (?:we|you|i|it) (?:have|see) (?P<rest>.+)$"), "exists", None),
    (re.compile(r"^(?:what|which) color (?:is|are) (?P<rest>.+)$"), "attribute", "colour"),
    (re.compile(r"^what is the color of (?P<rest>.+)$"), "attribute", "colour"),
    (re.compile(r"^(?:how big|what size|how large) (?:is|are) (?P<rest>.+)$"), "attribute", "size"),
    (re.compile(r"^(?:show me|show|find|give me|display|where is|where are|which is|what is) (?P<rest>(?:the |a )?(?:biggest|largest|smallest|tiniest|\w+ (?:closest|nearest)|closest|nearest)\b.*)$"), "show", None),
    (re.compile(r"^where (?:is|are|can i find|do i find|would i find) (?P<rest>.+)$"), "where", None),
    (re.compile(r"^(?:show me|show|display|find) (?P<rest>.+)$"), "list", None),
    (re.compile(r"^(?:list|name|enumerate) (?P<rest>.+)$"), "list", None),
    (re.compile(r"^(?:what|which)(?: objects?| things?)? (?:is|are) (?P<rest>(?:" + _REL_RE.pattern[2:-2] + r")\b.+)$"), "list", None),
    (re.compile(r"^(?:what|which) (?P<rest>.+?) (?:is|are) (?P<rel>(?:" + _REL_RE.pattern[2:-2] + r")\b.+)$"), "list", None),
    (re.compile(r"^what (?:objects|things) are (?:there )?(?P<rest>.*)$"), "list", None),
]

HELP = ("I can answer: how many <objects> [are there] [on/under/in/next to/near <object>] [in <room>] "
        "(e.g. how many cups are there; how many pieces of furniture; how many red chairs; how many big bowls; "
        "how many objects are on the table); is there a <object>?; what is on/next to <object>?; "
        "list the <objects>; what colour is the <object>?; how big is the <object>?; "
        "show me the biggest/smallest <object>; show me the <object> closest to <object>. "
        "Objects are COCO names (cup, chair, dining table, tv, ...), synonyms (mug, sofa, monitor, fridge) "
        "or groups (furniture, tableware, cutlery, electronics, appliance, food, kitchenware).")


def parse(question: str, is_room: Callable[[str], bool] = lambda name: False, embedding=None,
          use_embedding: bool = True) -> Query:
    """One question -> a Query, or ParseError with a helpful message.

    `is_room(name)` says whether a word after "in" names a stored room (location scope).
    """
    text = normalise(question)
    if not text:
        raise ParseError("empty question. " + HELP)
    for regex, form, attribute in FRAMES:
        m = regex.match(text)
        if m:
            rest = m.group("rest")
            if "rel" in m.groupdict() and m.group("rel"):
                rest = f"{rest} {m.group('rel')}"
            return _build(form, attribute, rest, is_room, embedding, use_embedding)
    raise ParseError(f"I don't understand '{question.strip()}'. " + HELP)


def _words(phrase: str) -> list[str]:
    return [w for w in phrase.split() if w not in FILLER]


def _split_room(text: str, is_room) -> tuple[str, Optional[str]]:
    """A trailing 'in (the) <room>' naming a stored room, or a non-object, is the location."""
    # "in front of the table" is a relation, not a room
    m = re.search(r"\b(?:in|inside) (?!front of\b)(?:the |my |this )?(?P<room>[a-z0-9' ]+?)(?: room)?$", text)
    if not m:
        return text, None
    room = m.group("room").strip()
    head = text[:m.start()].strip()
    if is_room(room) or is_room(room + " room"):
        return head, room if is_room(room) else room + " room"
    if resolve(room, use_embedding=False)[0] is None and room not in FILLER:
        return head, room        # not an object word: a room the store may not have (refused later)
    return text, None


def _noun_phrase(words: list[str], q: Query) -> str:
    """Strip attributes off a noun phrase into the query; the rest is the noun."""
    out = []
    for w in words:
        if w in COLOURS and q.colour is None:
            q.colour = COLOURS[w]
        elif w in SIZES and q.size is None:
            q.size = SIZES[w]
        elif w in SUPERLATIVES and q.superlative is None:
            q.superlative = SUPERLATIVES[w]
        else:
            out.append(w)
    return " ".join(out)


def _target(phrase: str, embedding, use_embedding: bool, implicit_any: bool) -> Target:
    if not phrase and implicit_any:
        return Target("", None, [], "any")
    parts = [p.strip() for p in re.split(r"\bor\b", phrase)] if re.search(r"\bor\b", phrase) else [phrase]
    if len(parts) > 1 and not all(parts):
        raise ParseError(f"'{phrase}': an 'or' needs an object on both sides. " + HELP)
    hits = []
    for part in parts:
        hit, why = resolve(part, embedding, use_embedding)
        if hit is None:
            raise ParseError(f"{why}. " + HELP)
        hits.append(hit)
    if len(hits) == 1:
        return hits[0]
    return _either(phrase, hits)


def _either(phrase: str, hits: list[Target]) -> Target:
    """'A or B' ('A / B'): one category if both name it, else every category named (how='either')."""
    if any(h.labels is None for h in hits):
        return Target(phrase, None, [], "any")
    if all(sorted(h.labels) == sorted(hits[0].labels) for h in hits):
        return hits[0]
    names = list(dict.fromkeys(n for h in hits for n in h.names))
    labels = sorted({lab for h in hits for lab in h.labels})
    return Target(phrase, labels, names, "either")


def _build(form, attribute, rest, is_room, embedding, use_embedding) -> Query:
    rest = " ".join(PIECES.sub(" ", EVERYWHERE.sub("", rest)).split())
    rest, room = _split_room(rest, is_room)
    q = Query(form=form, target=Target("", None), attribute=attribute, room=room)
    closest = CLOSEST.search(rest)
    if closest:
        head, anchor = rest[:closest.start()], rest[closest.end():]
        q.superlative = "closest"
        q.target = _target(_noun_phrase(_words(head), q), embedding, use_embedding, True)
        q.anchor = _target(_noun_phrase(_words(anchor), Query("x", q.target)), embedding, use_embedding, False)
        return q
    rel = _REL_RE.search(rest)
    head, anchor_text = (rest[:rel.start()], rest[rel.end():]) if rel else (rest, "")
    q.target = _target(_noun_phrase(_words(head), q), embedding, use_embedding,
                       implicit_any=form in ("list", "count", "exists") and rel is not None)
    if rel:
        q.relation, q.symmetric = RELATIONS[rel.group(1)]
        q.relation_word = rel.group(1)
        anchor_q = Query("anchor", q.target)
        q.anchor = _target(_noun_phrase(_words(anchor_text), anchor_q), embedding, use_embedding, False)
        if anchor_q.colour or anchor_q.size or anchor_q.superlative:
            raise ParseError("attributes of the object after a relation word are not supported. " + HELP)
    if form == "show" and q.superlative is None:
        q.form = "list"
    if form == "list" and q.superlative in ("max", "min"):
        q.form = "show"
    return q
