"""The compiler of logical forms (sg3d/queries/logic.py): templates read the scope, sets are computed.

A form whose every part is one of the simple forms (one kind of object, at most one stored
relation to another kind, a room) is answered by the per-form templates of sg3d/queries/vqa.py, which
have index-chosen variants for large stores. Every other form is compiled here into two reads,
`vqa_scene_objects` (the scope's objects; only those of the labels the question names when it
names no "objects"/"things") and `vqa_scene_relations` (their edges of the stored relation
types, from the whitelist), and its sets are
evaluated over those rows: relation filters, negation (the complement within the set), distance
bands (box centre to box centre), extremes, name look-ups, counts and comparisons. One round trip
each; no subqueries (their results on the embedded store are wrong).

Rules the answers follow (sg3d/queries/sets.py, sg3d/queries/answers.py; said in the answer where it matters):
- "objects"/"things" mean every object of the object layer, unnamed ones too; structure (floor,
  walls, counters, shelves, surfaces) is asked for by name.
- A colour word matches an object's main colour, as the per-room tallies count it; objects that
  have it only as their second colour (a white cup with red) are not counted, and the answer
  says how many there are.
- "how tall" is the box height along up; "how high" is the box top above the floor's top.
- No object of an asked class in scope: "I have not found ...", never "there is no ...".
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Callable, Optional

from sg3d.core.model import SHAPE_WORDS
from sg3d.queries.answers import OPS, Answerer
from sg3d.queries.grammar import SUPERLATIVES
from sg3d.queries.logic import NP, Filter, Form
from sg3d.queries.sets import (
    AFFORDANCES,
    COLOURS,
    EVERYWHERE,
    GENERIC,
    SIZES,
    STRUCTURE_LABELS,
    Evaluator,
    Resolved,
    Unanswerable,
)
from sg3d.queries.wording import plural

# -- from question text to answer -----------------------------------------------------------------
SIMPLE_OPS = ("count", "exists", "list", "where", "attribute", "rooms")
# words the per-form reader (sg3d/queries/parse.py) would pass over: a question holding one that the
# grammar cannot read is refused, naming it, rather than answered without it
UNREAD = ("not", "between", "more", "fewer", "less", "except", "without", "farther", "further",
          "closer", "nearer", "within", "apart", "distance", "far", "nor", "than")


def unread_word(text: str) -> Optional[str]:
    """The word of `text` that only the grammar reads (a number, 'not', 'closer'), the one
    that leads ("closer ... than": closer) where there are several."""
    words = text.split()
    hits = [w for w in words if w in UNREAD or any(c.isdigit() for c in w)]
    if not hits:
        return None
    return next((w for w in hits if w != "than"), hits[0])


def room_filters(form: Form, ev: Evaluator) -> list[Resolved]:
    """'in the kitchen' filters whose set is a room: taken out of the form (they set the scope)."""
    found = []

    def take(filters: list[Filter]) -> list[Filter]:
        keep = []
        for f in filters:
            if f.kind == "rel" and f.relation in ("in", "inside") and not f.negated and not f.other.alternatives \
                    and not f.other.filters:
                if " ".join(f.other.words) in EVERYWHERE:
                    continue            # "in the house": the whole scope
                r = ev.resolved(f.other, may_be_room=True)
                if r.kind == "room":
                    found.append(r)
                    continue
            visit(f.other)
            keep.append(f)
        return keep

    def visit(np: NP) -> None:
        for a in np.alternatives:
            visit(a)
        np.filters = take(np.filters)
        if np.toward is not None:
            visit(np.toward)

    form.filters = take(form.filters)
    for s in form.sets:
        visit(s)
    return found


def is_simple(form: Form, ev: Evaluator) -> bool:
    """One kind of object, at most one stored relation to one other kind, no number, colour,
    extreme or negation: the per-form templates of sg3d/queries/vqa.py answer it."""
    if form.op == "extreme":
        return _simple_extreme(form, ev)
    if form.op not in SIMPLE_OPS or len(form.sets) != 1:
        return False
    if form.op == "attribute" and form.attribute not in ("colour", "size"):
        return False
    head = form.sets[0]
    filters = list(head.filters) + list(form.filters)
    if len(filters) > 1:
        return False

    def plain(np: NP, with_colour: bool) -> bool:
        if np.alternatives:
            return all(plain(a, False) and not a.filters for a in np.alternatives)
        if np.number is not None or np.superlative or np.toward is not None:
            return False
        r = ev.resolved(np)
        return r.kind in ("named", "unknown") and r.shape is None and (with_colour or r.colour is None)

    if not plain(head, True) or (not head.alternatives and ev.resolved(head).size and filters):
        return False
    if filters:
        f = filters[0]
        if f.kind != "rel" or f.negated or f.other.filters or not plain(f.other, True) \
                or ev.resolved(f.other).size:
            return False
    return True


def labels_read(form: Form, ev: Evaluator) -> Optional[list[str]]:
    """The labels whose objects the form needs (the floor too: "how high" stands on it); None
    when a set is any object ("what is on the table") or the form is about rooms or
    affordances."""
    if form.op in ("affordance", "room_count", "rooms_next_to") or not form.sets:
        return None         # no set named: "what is on the table" asks about any object
    labels: set[str] = {"floor"}
    pending = list(form.sets) + [f.other for f in form.filters]
    while pending:
        np = pending.pop()
        if np.alternatives:
            pending += np.alternatives
            continue
        r = ev.resolved(np)
        if r.kind == "any":
            return None
        labels |= set(r.labels or [])
        pending += [f.other for f in np.filters] + ([np.toward] if np.toward is not None else [])
    return sorted(labels)


def _simple_extreme(form: Form, ev: Evaluator) -> bool:
    """"which bowl is the biggest (on the table)", "the cup closest to the sink": the per-form
    'show' answers (with the winner's thumbnail), for named kinds only."""
    head = form.sets[0] if form.sets else None
    if head is None or head.alternatives or head.number is not None or form.filters:
        return False
    r = ev.resolved(head)
    if r.kind != "named" or r.shape or r.size:
        return False
    if head.superlative in ("closest", "nearest"):
        other = head.toward
        if head.filters or other is None or other.filters or other.alternatives or other.number is not None:
            return False
        o = ev.resolved(other)
        return o.kind == "named" and o.colour is None and not o.size and not o.shape
    if SUPERLATIVES.get(head.superlative, ("", 0))[0] != "volume" or len(head.filters) > 1:
        return False
    return all(f.kind == "rel" and not f.negated and not f.other.filters and f.other.number is None
               and not f.other.alternatives and ev.resolved(f.other).kind == "named" and not f.other.superlative
               for f in head.filters)


# common English words a question may hold around its object words: never "fixed" into one
COMMON_WORDS = frozenset("""
with without from for into onto upon about after before again against along also always among
another anyone anybody because been being both could each either else even ever every except
here hers his how however into itself just like made make maybe might mine more most much must
near neither never none nothing now often only other others otherwise ours ourselves over own
perhaps quite rather really same shall should since such than that their theirs them themselves
then there these they this those though through thus till together too toward towards under
until very want wants want was were what whatever when whenever where wherever whether which
while who whom whose why will would yet your yours yourself want need needs look looking see
seen show tell know think thought wonder said say give given take taken keep kept leave left
right front back side sides part parts other inside outside middle center centre corner edge
white black made using used have having had does done doing going gone come comes came
glaze painted wooden metal plastic glass paper colour colours colored coloured
""".split())


def typo_vocabulary() -> frozenset:
    """Every word a question may use: the grammar's, the object nouns (singular and plural),
    colours, sizes, shapes, structure, affordance verbs and common question words."""
    return _vocabulary()


@functools.cache
def _vocabulary() -> frozenset:
    import json

    from sg3d.queries.grammar import RESERVED
    from sg3d.queries.lexicon import SYNONYMS, vocabulary
    from sg3d.queries.parse import FILLER
    from sg3d.queries.taxonomy import Taxonomy

    words: set[str] = set(RESERVED) | set(FILLER) | set(COLOURS) | set(SIZES) | set(SHAPE_WORDS)
    words |= set(STRUCTURE_LABELS) | GENERIC | {w for x in EVERYWHERE for w in x.split()} | {w for k in AFFORDANCES for w in k.split()}
    words |= {"please", "tell", "know", "could", "would", "should", "me", "us", "find", "put", "my",
              "cup", "does", "kitchen", "bedroom", "bathroom", "office", "living", "dining", "objects",
              "things", "items", "walls", "shelves", "surfaces", "counters", "color", "colors", "whats",
              "everything", "total", "type", "types", "kind", "kinds", "piece", "pieces", "sort",
              "sorts", "ones", "visible", "present", "stored", "there", "up", "down", "yes", "no",
              "left", "right", "front", "behind", "seen", "as", "bigger", "smaller", "larger",
              "size", "sizes", "hello", "thanks", "thank", "get", "where", "on", "top", "something"}
    words |= COMMON_WORDS
    nouns = set(vocabulary()) | set(Taxonomy.load().names)
    data = json.loads(SYNONYMS.read_text())
    nouns |= set(data["words"]) | set(data["any"])
    for n in nouns:
        parts = n.split()
        words |= set(parts)
        if parts:
            words.add(plural(parts[-1]))
    return frozenset(w for w in words if w)


@dataclass
class Outcome:
    """What the compiler made of a question: an answer, the fixed text for the per-form reader
    (`simple`), or a refusal."""

    kind: str                         # answer | simple | refuse | unread
    text: str = ""                    # the answer / refusal text, or the text to read per form
    op: str = ""
    value: object = None
    rows: list = field(default_factory=list)
    form: Optional[dict] = None       # the logical form, for --explain and --json
    notes: list[str] = field(default_factory=list)
    absent: bool = False
    room: Optional[str] = None        # the room the question names
    thumbnail: Optional[bytes] = None


def read_question(text: str, room_rows: Callable[[str], list], all_room_names: Callable[[], list]):
    """Normalised text -> Form, retrying with multi-word room names as one word each ("in my
    room", "in the living room": 'room' is a grammar word). GrammarError when neither reads."""
    from sg3d.queries.grammar import GrammarError, read

    try:
        return read(text), room_rows
    except GrammarError as first:
        if " room" not in f" {text}":
            raise
        out, placeholders = _room_placeholders(text, all_room_names())
        if not placeholders:
            raise first
        try:
            form = read(out)
        except GrammarError:
            raise first from None

        def rows(name: str) -> list:
            return room_rows(placeholders.get(name.split()[-1], name)) if name.split() and \
                name.split()[-1] in placeholders else room_rows(name)
        return form, rows


def _room_placeholders(text: str, stored: list) -> tuple[str, dict[str, str]]:
    """Multi-word room names in `text` replaced by one word each (token -> name as said): the
    stored names as written, then "<words> room" spans that name a stored room loosely
    ("the living room" -> `livingroom`, sg3d/queries/place_names.py)."""
    from sg3d.queries.place_names import match_name

    names = sorted((n.lower() for n in stored), key=len, reverse=True)
    placeholders: dict[str, str] = {}
    out = f" {text} "

    def put(name: str) -> None:
        i = len(placeholders)
        token = "roomname" + "abcdefghijklmnopqrstuvwxyz"[i % 26] * (1 + i // 26)
        placeholders[token] = name
        nonlocal out
        out = out.replace(f" {name} ", f" {token} ")

    for name in names:
        if f" {name} " in out:
            put(name)
    words = out.split()
    for j, w in enumerate(words):
        if w != "room":
            continue
        for i in range(max(0, j - 2), j):       # "living room", "guest bed room"
            span = " ".join(words[i:j + 1])
            if words[i] not in ("the", "a", "my", "this", "in") and match_name(span, names, typo_vocabulary()):
                put(span)
                break
    return out.strip(), placeholders


def compile_question(run, text: str, room: Optional[str], building: Optional[str], room_rows, all_room_names,
                     scope: Callable, embedding=None, use_embedding=True, evaluate: bool = False) -> Outcome:
    """Read `text` (normalised, typos fixed) and answer it, or say that the per-form reader
    should (a simple form; `evaluate`: answer it here all the same), or refuse naming the word
    not read."""
    from sg3d.queries.grammar import GrammarError

    try:
        form, rows_of = read_question(text, room_rows, all_room_names)
    except GrammarError as exc:
        if "has no unit" in str(exc):
            return Outcome("refuse", str(exc))
        word = unread_word(text)
        if word is not None:
            return Outcome("unread", f"I could not read '{word}' in this question", notes=[str(exc)])
        return Outcome("simple", text)
    if form.op == "list" and form.sets and form.sets[0].superlative:
        form.op = "extreme"          # "show me the biggest bowl"
    logical = form.form()
    ev = Evaluator(run, rows_of, embedding, use_embedding, building)
    try:
        found = room_filters(form, ev)
        q_room = found[0].room if found else None
        if q_room and room and q_room.lower() != room.lower():
            return Outcome("refuse", f"the question says '{q_room}' but --room is '{room}'", form=logical)
        # the per-form reader knows plain ASCII room names only ("küche", "my room" are ours)
        plain_room = q_room is None or (q_room.isascii() and q_room.split()[0] not in ("my", "our", "this"))
        if plain_room and not evaluate and is_simple(form, ev):
            return Outcome("simple", text, form=logical, room=q_room)
        ev.load(scope(q_room or room), labels_read(form, ev))
        label = q_room or room
        answerer = Answerer(ev, label)
        value_text, value, rows = OPS[form.op](answerer, form)
    except Unanswerable as exc:
        if ev.scene is None:
            # a word the compiler cannot place ("in the environment"): the per-form reader,
            # which knows such scope words, reads it or refuses
            return Outcome("simple", text, form=logical)
        return Outcome("refuse", str(exc), form=logical)
    return Outcome("answer", value_text, form.op if form.op != "extreme" else "show", value, rows, logical,
                   ev.notes, bool(ev.absent), q_room, answerer.thumbnail)

