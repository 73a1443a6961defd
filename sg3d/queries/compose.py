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

Rules the answers follow (sg3d/queries/sets.py, sg3d/queries/answer/operations.py; said in the answer where it matters):
- "objects"/"things" mean every object of the object layer, unnamed ones too; structure (floor,
  walls, counters, shelves, surfaces) is asked for by name.
- A colour word matches an object's main colour, as the per-room tallies count it; objects that
  have it only as their second colour (a white cup with red) are not counted, and the answer
  says how many there are.
- "how tall" is the box height along up; "how high" is the box top above the floor's top.
- No object of an asked class in scope: "I have not found ...", never "there is no ...".
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable, Iterator, Literal, Optional

from sg3d.core.relation_rules import VIEWPOINT
from sg3d.queries.answer.operations import OPS, Answerer
from sg3d.queries.lexicon import Target, lemma
from sg3d.queries.logic import NP, Filter, Form, Query
from sg3d.queries.reader.typos import typo_vocabulary
from sg3d.queries.sets import Evaluator, Resolved, Unanswerable
from sg3d.queries.vocabulary import (
    EVERYWHERE,
    INVERSE,
    RELATIONS,
    STORED_TYPES,
    SUPERLATIVES,
)

# -- from question text to answer -----------------------------------------------------------------
SIMPLE_OPS = ("count", "exists", "list", "where", "attribute", "rooms")
# words that carry a condition (a number, a negation, a distance): a question holding one that the
# grammar cannot read is refused naming it (the one that leads), rather than answered without it
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
                r = _room_or_object(ev, f.other)
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

    form.filters[:] = take(form.filters)
    for s in form.sets:
        visit(s)
    return found


def _room_or_object(ev: Evaluator, np: NP) -> Resolved:
    """What "in X" names: a stored room, else an object; a word that is neither is refused as a
    room the store does not hold (with the rooms it holds)."""
    try:
        return ev.resolved(np, may_be_room=True)
    except Unanswerable:
        if np.number is not None or np.alternatives or len(np.words) > 3:
            raise
        rows = ev.run.read("vqa_room_names", building=ev.building)
        stored = ", ".join(sorted({f"{r['building']}/{r['name']}" for r in rows})) or "none"
        raise Unanswerable(f"no room '{np.text()}' in the store (rooms: {stored})") from None


def is_simple(form: Form, ev: Evaluator) -> bool:
    """One kind of object, at most one stored relation to one other kind, no number, colour,
    extreme or negation: the per-form templates of sg3d/queries/vqa.py answer it."""
    if form.op == "extreme":
        return _simple_extreme(form, ev)
    if form.lacking or form.number is not None or \
            any(s.alternatives and s.joined == "and" for s in form.sets) and form.op == "rooms":
        return False            # "rooms with a chair but no fridge", "with a chair and a tv": sets
    sets = form.sets or ([NP([])] if form.op == "list" else [])    # "what is behind the table"
    if form.op not in SIMPLE_OPS or len(sets) != 1:
        return False
    if form.op == "attribute" and form.attribute not in ("colour", "size"):
        return False
    head = sets[0]
    filters = list(head.filters) + list(form.filters)
    if len(filters) > 1:
        return False
    # a viewpoint relation is computed from boxes for any set ("what is behind the table")
    seen = bool(filters) and filters[0].kind == "rel" and RELATIONS[filters[0].relation or ""][0] in VIEWPOINT
    kinds = ("named", "unknown", "any") if seen else ("named", "unknown")

    def plain(np: NP, with_colour: bool) -> bool:
        if np.alternatives:
            return all(plain(a, False) and not a.filters for a in np.alternatives)
        if np.number is not None or np.superlative or np.toward is not None or np.purpose:
            return False
        r = ev.resolved(np)
        return r.kind in kinds and r.shape is None and (with_colour or r.colour is None)

    if not plain(head, True) or (not head.alternatives and ev.resolved(head).size and filters):
        return False
    if filters:
        f = filters[0]
        # "above the desk" is read both ways (desk -UNDER-> chair): over the scene's edges
        if f.kind != "rel" or f.negated or f.reverse or f.other.filters or not plain(f.other, True) \
                or RELATIONS[f.relation or ""][0] in INVERSE \
                or ev.resolved(f.other).size:
            return False
    return True


def neighbours(form: Form) -> bool:
    """"which room has the fewest neighbours": rooms counted by their ADJACENT_TO links."""
    from sg3d.queries.answer.operations import NEIGHBOUR_WORDS
    from sg3d.queries.lexicon import lemma

    return form.op == "room_most" and len(form.sets) == 1 and \
        " ".join(lemma(w) for w in form.sets[0].words) in NEIGHBOUR_WORDS


# the forms over the rooms of a walk alone (sg3d/queries/walk.py): no object set is evaluated
WALK_OPS = frozenset({"rooms_next_hold", "route"})


def labels_read(form: Form, ev: Evaluator) -> Optional[list[str]]:
    """The labels whose objects the form needs (the floor too: "how high" stands on it); None
    when a set is any object ("what is on the table") or the form is about rooms or
    affordances."""
    if form.op in WALK_OPS:
        return []           # the rooms of a walk and what they hold are read by their own template
    if form.op in ("affordance", "room_count", "rooms_next_to") or not form.sets or neighbours(form):
        return None         # no set named: "what is on the table" asks about any object
    labels: set[str] = {"floor"}
    for r in _resolved_sets(list(form.sets) + [f.other for f in form.filters] + list(form.lacking), ev):
        if r.kind == "any":
            return None
        labels |= set(r.labels or [])
    return sorted(labels)


def _resolved_sets(nps: list[NP], ev: Evaluator) -> Iterator[Resolved]:
    """Each set the noun phrases name, resolved: their alternatives apart, and the sets their own
    filters and "toward" name in turn (last named first)."""
    pending = list(nps)
    while pending:
        np = pending.pop()
        if np.alternatives:
            pending += np.alternatives
            continue
        yield ev.resolved(np)
        pending += [f.other for f in np.filters] + ([np.toward] if np.toward is not None else [])


# The forms whose answer is the set of objects asked about, as it is (no object outside it is read).
ANCHORED_OPS = frozenset({"list", "count", "exists"})


def _any_head(form: Form, ev: Evaluator):
    """(its one set of any object, resolved; the filters on it) when the form is one of
    ANCHORED_OPS about one set of any object with no size, shape, number, purpose, extreme or
    alternatives of its own; else None."""
    if form.op not in ANCHORED_OPS or len(form.sets) > 1 or form.lacking or form.number is not None \
            or form.seen_from is not None or form.among:
        return None
    head = form.sets[0] if form.sets else NP([])
    if head.alternatives or head.number is not None or head.superlative or head.toward is not None \
            or head.purpose or head.pronoun:
        return None
    r = ev.resolved(head)
    if r.kind != "any" or r.size or r.shape:
        return None
    return r, list(head.filters) + list(form.filters)


def _named_labels(filters: list[Filter], ev: Evaluator) -> Optional[set[str]]:
    """The labels of every set the filters name, the floor too; None when one is not a named kind."""
    labels: set[str] = {"floor"}
    for other in _resolved_sets([f.other for f in filters], ev):
        if other.kind not in ("named", "structure", "unknown"):
            return None
        labels |= set(other.labels or [])
    return labels


def anchor_labels(form: Form, ev: Evaluator) -> Optional[list[str]]:
    """Rule "read from the anchor outwards": a form about any object ("what", "things") held to
    a named kind by a stored relation ("what is on the table", "how many things are next to the
    sink", "anything on the shelves besides the cups") needs only the objects of every kind it
    names (the anchors, and the floor) and the objects linked to them. Their labels when the
    form is one of ANCHORED_OPS; its one set of any object has no colour, size, shape, number,
    purpose, extreme or alternatives of its own and at least one filter that is a relation (not a
    negated one) to a named kind; and every other set it names is a named kind. None otherwise:
    the whole scope is read."""
    found = _any_head(form, ev)
    if found is None or found[0].colour:
        return None
    filters = found[1]
    if not any(f.kind == "rel" and not f.negated and RELATIONS[f.relation or ""][0] in STORED_TYPES
               for f in filters):
        return None
    labels = _named_labels(filters, ev)
    return None if labels is None else sorted(labels)


def colour_read(form: Form, ev: Evaluator) -> Optional[tuple[list[str], str]]:
    """Rule "read by colour": a form about any object of a colour ("what is red", "anything
    purple on the table?") needs only the objects whose main or second colour it is (the second
    is reported) and the objects of every kind it names: (those labels, the colour) under the
    conditions of `anchor_labels` but with a colour and with or without filters; None otherwise."""
    found = _any_head(form, ev)
    if found is None or not found[0].colour:
        return None
    labels = _named_labels(found[1], ev)
    return None if labels is None else (sorted(labels), found[0].colour)


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
    if SUPERLATIVES.get(head.superlative or "", ("", 0))[0] != "volume" or len(head.filters) > 1:
        return False
    return all(f.kind == "rel" and not f.negated and not f.other.filters and f.other.number is None
               and not f.other.alternatives and ev.resolved(f.other).kind == "named" and not f.other.superlative
               for f in head.filters)


@dataclass
class Outcome:
    """What the compiler made of a question: an answer (of set operations), or a refusal."""

    kind: str                         # answer | refuse | unread
    text: str = ""                    # the answer / refusal text
    op: str = ""
    value: object = None
    rows: list = field(default_factory=list)
    form: Optional[dict] = None       # the logical form, for --explain and --json
    notes: list[str] = field(default_factory=list)
    absent: bool = False
    room: Optional[str] = None        # the room the question names
    thumbnail: Optional[bytes] = None


def grammar_refusal(text: str, exc) -> Outcome:
    """The grammar stopped: refuse naming the word it could not read (a word that carries a
    condition first, then where reading stopped, else the whole text)."""
    from sg3d.queries.reader.grammar import ReaderFailure

    if "has no unit" in str(exc) or "to what?" in str(exc):
        return Outcome("refuse", str(exc))
    if isinstance(exc, ReaderFailure):     # the reader failed (logged): where it stopped
        return Outcome("unread", f"I stopped reading this question at '{exc.word or text[:60]}'", notes=[str(exc)])
    word = unread_word(text) or _unknown_before(text, exc.word) or exc.word
    if word is None:
        said = text if len(text) <= 60 else text[:57] + "..."
        return Outcome("unread", f"I could not read '{said}' as a question", notes=[str(exc)])
    return Outcome("unread", f"I could not read '{word}' in this question", notes=[str(exc)])


def _unknown_before(text: str, stopped: Optional[str]) -> Optional[str]:
    """Where the reader stopped at a word it knows ('the' in "blorp the frobnicator", 'of' in
    "what is the meaning of life"), the word to name is the first one before it that no word
    list holds ('blorp', 'meaning'); None when the stop word is itself unknown or none is."""
    if stopped is None or stopped not in typo_vocabulary():
        return None
    words = [w.strip(".,;:!?'\"") for w in text.split()]
    before = words[:words.index(stopped)] if stopped in words else words
    return next((w for w in before if w and w not in typo_vocabulary() and not any(c.isdigit() for c in w)), None)


def planned(form: Form) -> Form:
    """The form as the plan reads it: "show me the biggest bowl" (a list with an extreme) is the extreme."""
    return replace(form, op="extreme") if form.op == "list" and form.sets and form.sets[0].superlative else form


Executor = Literal["templates", "sets"]


@dataclass(frozen=True)
class Plan:
    """How a read form is answered, the one seam between planning and running: by the per-form
    templates (`templates`: its Query, over the rooms the question names) or by set operations
    over the scope's scene read (`sets`, `run_sets`)."""

    executor: Executor
    form: Form
    logical: dict                     # the form as read, for --explain and --json
    ev: Evaluator
    room: Optional[str]               # the room the question names
    room_ids: Optional[list[str]]     # templates: the rooms it names (None: the scope); sets: the rooms read
    query: Optional[Query] = None     # templates: what they run with


def plan(ev: Evaluator, form: Form, room: Optional[str], scope: Callable) -> "Plan | Outcome":
    """Plan a read form: a simple one becomes a Query for the per-form templates, any other is
    answered by set operations over the scope's rows; or an Outcome refusing it, naming the word."""
    form = planned(form)
    logical = form.form()
    try:
        found = room_filters(form, ev)
        q_room = found[0].room if found else None
        if q_room and room and q_room.lower() != room.lower():
            return Outcome("refuse", f"the question says '{q_room}' but --room is '{room}'", form=logical)
        if is_simple(form, ev):
            return Plan("templates", form, logical, ev, q_room, found[0].room_ids if found else None,
                        plan_simple(form, ev, q_room))
        return Plan("sets", form, logical, ev, q_room, found[0].room_ids if found else scope(room))
    except Unanswerable as exc:
        # a word that names nothing (before any scene is read): refused with an example
        return Outcome("unread" if ev.scene is None else "refuse", str(exc), form=logical)


def run_sets(p: Plan, room: Optional[str]) -> Outcome:
    """A plan of set operations run: the scope's scene read (only the kinds the form names), the
    form's operation answered over it."""
    form, ev = p.form, p.ev
    try:
        anchors = anchor_labels(form, ev)
        coloured = None if anchors is not None else colour_read(form, ev)
        if anchors is not None:
            ev.load(p.room_ids, anchors, anchored=True)
        elif coloured is not None:
            ev.load(p.room_ids, coloured[0], colour=coloured[1])
        else:
            ev.load(p.room_ids, labels_read(form, ev))
        answerer = Answerer(ev, p.room or room)
        value_text, value, rows = OPS[form.op](answerer, form)
    except Unanswerable as exc:
        return Outcome("unread" if ev.scene is None else "refuse", str(exc), form=p.logical)
    return Outcome("answer", value_text, form.op if form.op != "extreme" else "show", value, rows, p.logical,
                   ev.notes, bool(ev.absent), p.room, answerer.thumbnail)


# -- the planner: a simple form as the per-form templates' Query -----------------------------------
def _target(np: NP, ev: Evaluator) -> Target:
    """What a set's words name, as the per-form templates take it."""
    if np.alternatives:
        return _either(" or ".join(a.text() for a in np.alternatives), [_target(a, ev) for a in np.alternatives])
    r = ev.resolved(np)
    if r.target is not None:
        t = r.target
        return Target(t.phrase, list(t.labels) if t.labels is not None else None, list(t.names), t.how,
                      t.similarity, list(t.ignored))
    return Target(np.text(), r.labels, list(r.names), "any" if r.kind == "any" else "label")


def _either(phrase: str, hits: list[Target]) -> Target:
    """'A or B', 'A / B', 'A and B': one category if both name it, else every category named
    (how='either'; "how many tables and chairs" counts both)."""
    if any(h.labels is None for h in hits):
        return Target(phrase, None, [], "any")
    ignored = [w for h in hits for w in h.ignored]
    known = [h for h in hits if h.how != "unknown"] or hits
    if all(sorted(h.labels or []) == sorted(known[0].labels or []) for h in known):
        first = known[0]
        return Target(phrase, first.labels, first.names, first.how, first.similarity, ignored)
    names = list(dict.fromkeys(n for h in known for n in h.names))
    labels = sorted({lab for h in known for lab in h.labels or []})
    return Target(phrase, labels, names, "either", ignored=ignored)


def plan_simple(form: Form, ev: Evaluator, room: Optional[str]) -> Query:
    """A simple form (`is_simple`) -> the Query the per-form templates run with: one target, its
    colour and size, at most one relation to an anchor, or an extreme ("show")."""
    head = form.sets[0] if form.sets else NP([])
    q = Query(form="show" if form.op == "extreme" else form.op, target=_target(head, ev), room=room,
              attribute=form.attribute if form.op == "attribute" else None)
    # "the cup" means one cup: an answer about several says so and asks which
    q.one = head.definite and not head.indefinite and not head.alternatives and bool(head.words) \
        and head.words[-1] == lemma(head.words[-1]) and head.number is None
    if not head.alternatives:
        r = ev.resolved(head)
        q.colour, q.size = r.colour, r.size
    q.ignored = list(q.target.ignored) + list(head.ignored)
    if form.op == "extreme" and head.superlative in ("closest", "nearest") and head.toward is not None:
        q.superlative, q.anchor = "closest", _target(head.toward, ev)
        return q
    if form.op == "extreme":
        q.superlative = "max" if SUPERLATIVES[head.superlative or "biggest"][1] > 0 else "min"
    filters = list(head.filters) + list(form.filters)
    if filters:
        f = filters[0]
        q.relation, q.symmetric = RELATIONS[f.relation or ""]
        q.relation_word = f.relation
        q.anchor = _target(f.other, ev)
        q.anchor_article = "a" if f.other.indefinite and not f.other.alternatives else "the"
        if not f.other.alternatives:
            q.anchor_colour = ev.resolved(f.other).colour
        q.ignored += list(q.anchor.ignored) + list(f.other.ignored)
    return q


def plan_question(question: str, embedding=None, use_embedding: bool = True) -> Query:
    """The plan of a simple question without a store (no room names known): what the per-form
    templates would run with. GrammarError or Unanswerable when it is not read, or not simple."""
    from sg3d.queries.reader.grammar import read
    from sg3d.queries.reader.tidy import tidy

    form = read(tidy(question).text)
    ev = Evaluator(None, lambda name: [], embedding, use_embedding)
    if not is_simple(form, ev):
        raise Unanswerable(f"'{question}' is not a simple question (one kind, at most one relation)")
    return plan_simple(form, ev, None)
