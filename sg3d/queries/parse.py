"""Question text -> query form, by rules (no LLM): frame regexes, then the noun phrases.

The parser only produces plain data (`Query`); words never reach Cypher except as parameters,
and relation words map to whitelisted relation types through the fixed `RELATIONS` table.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Callable, Optional

from sg3d.core.errors import Sg3dError
from sg3d.core.model import COLOUR_NAMES
from sg3d.queries.lexicon import Target, resolve

# relation phrase -> (relation type, symmetric?); longest phrases are tried first
RELATIONS: dict[str, tuple[str, bool]] = {
    "on top of": ("ON", False), "on": ("ON", False), "sitting on": ("ON", False),
    "under": ("UNDER", False), "underneath": ("UNDER", False), "beneath": ("UNDER", False),
    "below": ("BELOW", False), "above": ("ABOVE", False), "over": ("ABOVE", False),
    "inside": ("IN", False), "in": ("IN", False), "within": ("IN", False),
    "next to": ("NEXT_TO", True), "beside": ("NEXT_TO", True), "by": ("NEXT_TO", True),
    "near": ("NEAR", True), "close to": ("NEAR", True), "around": ("NEAR", True),
    "nearby": ("NEAR", True), "alongside": ("NEXT_TO", True), "adjacent to": ("NEXT_TO", True),
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


class ParseError(Sg3dError, ValueError):
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
    anchor_colour: Optional[str] = None     # "next to the red controller"
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


PARENTHETICAL = re.compile(r"\([^()]*\)|\[[^\[\]]*\]")
# a title in quotes ("the 'Computer' magazine") names a copy, not a kind: not used, reported
QUOTED = re.compile(r"(?<![A-Za-z])['\"\u2018\u201c]([^'\"\u2019\u201d]{1,40})['\"\u2019\u201d](?![A-Za-z])")
CONTRACTIONS = {"what's": "what is", "where's": "where is", "there's": "there is", "which's": "which is",
                "that's": "that is", "how's": "how is", "it's": "it is"}
# posture verbs say nothing the graph stores beyond the relation after them: "what lies on X"
POSTURE = [(re.compile(r"\b(is|are) (?:mounted|placed|located|sitting|standing|lying|hanging|kept|stored|"
                       r"resting|put|positioned|found|situated|set)\b"), r"\1"),
           (re.compile(r"\b(?:lies|sits|stands|rests|hangs|stays)\b"), "is"),
           (re.compile(r"\b(?:lie|sit|stand|rest|hang)\b(?= (?:on|under|in|inside|above|below|next|near|beside|by))"),
            "are")]
# the room's shell is not stored as objects, and parts of an object are not resolved: dropped, reported
SHELL = re.compile(r"\b(?:on|against|from|along|to|by|at) the (?:walls?|floor|ground|ceiling)\b")
PART_OF = re.compile(r"\bthe (?:left|right|far|near|front|back|top|bottom|middle|other|upper|lower) "
                     r"(?:end|side|part|corner|half|edge|shelf)s? of\b")
# "in the room", "here": the scope given by --room (or the whole store)
HERE = re.compile(r"\b(?:(?:in|inside|within) (?:the|this|my|our) (?:room|place|space|area)|in here|here)\b")


def clean(question: str) -> tuple[str, list[str]]:
    """Question -> (normalised text, what was dropped as not used: asides, titles, walls)."""
    dropped: list[str] = []
    text = question
    # parenthetical remarks "( ... )" are asides, not part of the question (innermost first)
    while True:
        found = PARENTHETICAL.findall(text)
        if not found:
            break
        dropped += [f.strip() for f in found]
        text = PARENTHETICAL.sub(" ", text)
    dropped += [f"'{m}' (a title)" for m in QUOTED.findall(text)]
    text = QUOTED.sub(" ", text)
    text = text.lower().replace("\u2019", "'")
    for k, v in CONTRACTIONS.items():
        text = re.sub(rf"\b{re.escape(k)}", v, text)
    # "A / B", "A + B" and "A and/or B" name alternatives: read as "A or B"
    text = re.sub(r"\band\s*/\s*or\b", " or ", text)
    text = re.sub(r"\s*[/+&]\s*", " or ", text)
    text = text.replace("colour", "color")
    text = re.sub(r"[^a-z0-9' ]+", " ", text)
    text = " ".join(text.replace("'", " ").split())
    for regex, repl in POSTURE:
        text = regex.sub(repl, text)
    for regex in (SHELL, PART_OF):
        dropped += regex.findall(text)
        text = regex.sub(" ", text)
    text = HERE.sub(" ", text)
    return " ".join(text.split()), dropped


def normalise(text: str) -> str:
    return clean(text)[0]


_REL = _REL_RE.pattern[2:-2]
_SUP = r"(?:biggest|largest|smallest|tiniest)"
# (regex, form, attribute) — the question frames, tried in order
FRAMES: list[tuple[re.Pattern, str, Optional[str]]] = [
    # which rooms hold an object: before "what/which ... is" and "is there"
    (re.compile(r"^(?:which|what) rooms? (?:has|have|holds?|contains?) (?P<rest>.+)$"), "rooms", None),
    (re.compile(r"^in (?:which|what) rooms? (?:is|are) (?:there )?(?P<rest>.+)$"), "rooms", None),
    (re.compile(r"^how many (?P<rest>.+)$"), "count", None),
    (re.compile(r"^what(?: is the)? number of (?P<rest>.+)$"), "count", None),
    (re.compile(r"^count (?:the )?(?P<rest>.+)$"), "count", None),
    (re.compile(r"^(?:is|are) there (?P<rest>.+)$"), "exists", None),
    (re.compile(r"^(?:do|does|can) (?:we|you|i|it|the room|this room) (?:have|see|contain|hold) (?P<rest>.+)$"), "exists", None),
    (re.compile(r"^(?:does|do) (?:the |this |my )?(?P<room>[a-z ]+?) (?:have|contain|hold) (?P<rest>.+)$"), "exists", None),
    # yes/no about a relation: "is the cup on the table", "are the mugs next to the sink"
    (re.compile(r"^(?:is|are) (?P<rest>.+? (?:" + _REL + r")\b.+)$"), "exists", None),
    # yes/no about a stored attribute: "is the cup red", "are the chairs big"
    (re.compile(r"^(?:is|are) (?P<rest>.+ (?:" + "|".join(sorted(set(COLOURS) | set(SIZES))) + r"))$"), "exists", None),
    (re.compile(r"^(?:what|which) color (?:is|are) (?P<rest>.+)$"), "attribute", "colour"),
    (re.compile(r"^what is the color of (?P<rest>.+)$"), "attribute", "colour"),
    (re.compile(r"^(?:how big|what size|how large) (?:is|are) (?P<rest>.+)$"), "attribute", "size"),
    # superlatives: "which cup is the biggest", "which is the largest object on the table"
    (re.compile(r"^(?:which|what) (?:one )?(?P<rest>.+?) (?:is|are) (?:the )?(?P<rel>" + _SUP + r"\b.*)$"), "show", None),
    (re.compile(r"^(?:which|what) (?P<rest>.+?) (?:is|are) (?:the )?(?P<rel>(?:closest|nearest)\b.+)$"), "show", None),
    (re.compile(r"^(?:show me|show|find|give me|display|where is|where are|which is|what is|which are|what are) (?P<rest>(?:the |a )?(?:" + _SUP[3:-1] + r"|\w+ (?:closest|nearest)|closest|nearest)\b.*)$"), "show", None),
    (re.compile(r"^(?:the )?(?P<rest>" + _SUP + r" .+)$"), "show", None),
    (re.compile(r"^where (?:is|are|can i find|do i find|would i find) (?P<rest>.+)$"), "where", None),
    (re.compile(r"^(?:show me|show|display|find) (?P<rest>.+)$"), "list", None),
    (re.compile(r"^(?:list|name|enumerate) (?P<rest>.+)$"), "list", None),
    # listing a room: "what objects are in the kitchen", "what is there", "what do you see"
    (re.compile(r"^(?:what|which) (?:objects? |things? |items? |stuff )?(?:is|are|do you see|can you see|can i see|"
                r"do we have|do you have|is there|are there)(?: there)?(?P<rest>)$"), "list", None),
    (re.compile(r"^(?:what|which)(?: objects?| things?| items?)? (?:is|are) (?:there )?(?P<rest>(?:" + _REL + r")\b.+)$"), "list", None),
    (re.compile(r"^(?:what|which) (?P<rest>.+?) (?:is|are) (?P<rel>(?:" + _REL + r")\b.+)$"), "list", None),
    (re.compile(r"^what (?:objects|things|items) (?:are|is) (?:there )?(?P<rest>.*)$"), "list", None),
    (re.compile(r"^(?:what|which) (?P<rest>.+?) (?:is|are) (?:there|visible|present|stored)(?P<rel>.*)$"), "list", None),
]

# one example per kind of question; a refusal offers the one closest to what was asked
EXAMPLES = [
    "how many cups are there?", "how many chairs are in the room?", "how many red chairs are there?",
    "how many cups or mugs are on the table?", "how many pieces of furniture are there?",
    "is there a sink?", "is the cup on the table?", "what is on the table?", "what is next to the sink?",
    "what objects are in the kitchen?", "what colour is the couch?", "how big is the table?",
    "which cup is the biggest?", "show me the cup closest to the sink", "where is the keyboard?",
    "which rooms have a chair?",
]


def example_for(question: str) -> str:
    """The example question closest to `question` (shared words first, then spelling)."""
    import difflib

    words = set(normalise(question).split())
    return max(EXAMPLES, key=lambda e: (len(words & set(normalise(e).split())),
                                        difflib.SequenceMatcher(None, question.lower(), e).ratio()))


def refusal(why: str, question: str) -> str:
    """One short line: what was not understood, and one example close to the question."""
    return f"{why}; try e.g. \"{example_for(question)}\""


HELP = "ask e.g. " + "; ".join(EXAMPLES[:6])


def parse(question: str, is_room: Callable[[str], bool] = lambda name: False, embedding=None,
          use_embedding: bool = True) -> Query:
    """One question -> a Query, or ParseError saying what was not understood.

    `is_room(name)` says whether a word after "in" names a stored room (location scope).
    """
    text, dropped = clean(question)
    if not text:
        raise ParseError("empty question")
    for regex, form, attribute in FRAMES:
        m = regex.match(text)
        if m:
            groups = m.groupdict()
            rest = m.group("rest")
            if groups.get("rel"):
                rest = f"{rest} {m.group('rel')}"
            if groups.get("room"):
                rest = f"{rest} in {m.group('room')}"
            q = _build(form, attribute, rest, is_room, embedding, use_embedding)
            q.ignored = dropped + q.ignored
            return q
    raise ParseError("I don't understand the form of this question")


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
    split = re.compile(r"\b(?:or|and|as well as|plus)\b")
    parts = [p.strip() for p in split.split(phrase)] if split.search(phrase) else [phrase]
    parts = [p for p in parts if p]
    if not parts:
        raise ParseError("no object named")
    hits = []
    for part in parts:
        hit, why = resolve(part, embedding, use_embedding)
        if hit is None:
            raise ParseError(why)
        hits.append(hit)
    if len(hits) == 1:
        return hits[0]
    return _either(phrase, hits)


def _either(phrase: str, hits: list[Target]) -> Target:
    """'A or B', 'A / B', 'A and B': one category if both name it, else every category named
    (how='either'; "how many tables and chairs" counts both)."""
    if any(h.labels is None for h in hits):
        return Target(phrase, None, [], "any")
    ignored = [w for h in hits for w in h.ignored]
    known = [h for h in hits if h.how != "unknown"] or hits
    if all(sorted(h.labels or []) == sorted(known[0].labels or []) for h in known):   # none is None here
        first = known[0]
        return Target(phrase, first.labels, first.names, first.how, first.similarity, ignored)
    names = list(dict.fromkeys(n for h in known for n in h.names))
    labels = sorted({lab for h in known for lab in h.labels or []})
    return Target(phrase, labels, names, "either", ignored=ignored)


# "mugs that have a red pattern", "cups with a handle": the clause may hold a colour or size
HAVING = re.compile(r"\b(?:that|which|who)? ?(?:have|has|having|with|featuring|showing)\b(?P<clause>.*?)(?=\b(?:" + _REL + r")\b|$)")


def _attribute_clause(rest: str, q: Query) -> str:
    """Take a 'with/have ...' clause out of the phrase: its colour/size words go into the query,
    the other words are reported as ignored."""
    m = HAVING.search(rest)
    if not m or not m.group("clause").strip():
        return rest
    words = _words(m.group("clause"))
    left = _noun_phrase(words, q).split()
    q.ignored += [w for w in left if w not in ("it", "them", "on", "a", "an")]
    return (rest[:m.start()] + " " + rest[m.end():]).strip()


def _build(form, attribute, rest, is_room, embedding, use_embedding) -> Query:
    rest = " ".join(PIECES.sub(" ", EVERYWHERE.sub("", rest)).split())
    rest, room = _split_room(rest, is_room)
    q = Query(form=form, target=Target("", None), attribute=attribute, room=room)
    if form in ("count", "exists", "list", "show", "rooms"):
        rest = _attribute_clause(rest, q)
    closest = CLOSEST.search(rest)
    if closest:
        head, anchor = rest[:closest.start()], rest[closest.end():]
        q.superlative = "closest"
        q.target = _target(_noun_phrase(_words(head), q), embedding, use_embedding, True)
        q.anchor = _target(_noun_phrase(_words(anchor), Query("x", q.target)), embedding, use_embedding, False)
        q.ignored += q.target.ignored + q.anchor.ignored
        return q
    rel = _REL_RE.search(rest)
    head, anchor_text = (rest[:rel.start()], rest[rel.end():]) if rel else (rest, "")
    q.target = _target(_noun_phrase(_words(head), q), embedding, use_embedding,
                       implicit_any=form in ("list", "count", "exists", "show") and (rel is not None or form == "list"))
    if rel:
        q.relation, q.symmetric = RELATIONS[rel.group(1)]
        q.relation_word = rel.group(1)
        anchor_q = Query("anchor", q.target)
        q.anchor = _target(_noun_phrase(_words(anchor_text), anchor_q), embedding, use_embedding, False)
        if anchor_q.size or anchor_q.superlative:
            raise ParseError("a size word on the object after a relation word is not supported")
        q.anchor_colour = anchor_q.colour
        q.ignored += q.anchor.ignored
    q.ignored = q.target.ignored + q.ignored
    if form == "show" and q.superlative is None:
        q.form = "list"
    if form == "list" and q.superlative in ("max", "min"):
        q.form = "show"
    return q


# Questions about re-scans (issue #17), answered from the scans' history (sg3d/app/changes.py):
# "what changed in the kitchen", "what is gone", "where was the cup before".
CHANGE_FRAMES: list[tuple[re.Pattern, str]] = [
    (re.compile(r"^what (?:has |have )?(?:changed|is different|moved)(?: since (?:the )?last (?:scan|time))?(?P<rest>.*)$"),
     "changes"),
    (re.compile(r"^what (?:is|are|has|have) (?:been )?(?:gone|missing|disappeared|removed|taken away)(?P<rest>.*)$"), "gone"),
    (re.compile(r"^what (?:disappeared|went missing|was removed|were removed|vanished)(?P<rest>.*)$"), "gone"),
    (re.compile(r"^where (?:was|were|did) (?P<rest>.+?) (?:before|previously|earlier|yesterday|used to be|stand before)$"),
     "before"),
]


@dataclass
class ChangeQuery:
    form: str                        # changes | gone | before
    target: Optional[Target] = None  # "before": the objects asked about
    room: Optional[str] = None


def parse_change(question: str, is_room: Callable[[str], bool] = lambda name: False,
                 embedding=None) -> Optional[ChangeQuery]:
    """A question about what re-scans changed -> ChangeQuery; None when it is no such question
    (then `parse` reads it); ParseError when it is one but its object is not understood."""
    text, _ = clean(question)
    for regex, form in CHANGE_FRAMES:
        m = regex.match(text)
        if not m:
            continue
        rest, room = _split_room(m.group("rest").strip(), is_room)
        if form != "before":
            if rest and _words(rest):
                continue            # "what changed the colour of ..." is not a question about scans
            return ChangeQuery(form, room=room)
        target, why = resolve(" ".join(_words(rest)), embedding=embedding)
        if target is None or not target.labels:
            raise ParseError(why or f"I don't know what '{rest}' is")
        return ChangeQuery(form, target=target, room=room)
    return None
