"""`sg3d ask`: question -> query form -> Cypher template -> answer (paper Sec. VI-A).

Entry point: `answer(store, question, room=None, building=None) -> Answer`. The question is read
once, by the grammar (sg3d/queries/reader/grammar.py), into a logical form (sg3d/queries/logic.py); the
planner (sg3d/queries/compose.py) turns a simple form into a `Query` for the per-form functions
here, and answers every other form over the scope's rows. One function per
query form (`count`, `exists`, `list_objects`, `attribute`, `show`); each runs templates of
`cypher/vqa_*.cypher` in READ transactions with the question's words as parameters only. The
one write is `ensure_taxonomy` (once per store and taxonomy version). An unparsed or
unanswerable question gives `Answer(ok=False)` with a message saying what can be asked: a
refusal, never a guessed number.

"Big"/"small" compare an object's volume (w*d*h of its box) with the MEDIAN volume of all stored
objects of its own label (strictly above = big, strictly below = small), so "a big cup" and
"a big table" each mean big for their kind, and a scope (--room) does not change the yardstick.
The medians are computed in the store (percentileCont), one row per label, not from every volume.

Access paths (measured with EXPLAIN/PROFILE on ArcadeDB, 100k objects in 1,000 rooms): a
`($x IS NULL OR o.prop ...)` test on an indexed property makes the planner scan every Object,
and `o.room IN $rooms AND o.label IN $labels` picks the label index (every object of the
label). So each template comes in variants chosen here: `*_in_rooms` starts from the Room
nodes (unique index) and follows CONTAINS; the plain one starts from the object_label index;
`*_any` (no label asked, no small scope) is the one that scans. See `_variant`.

Round trips: on the embedded store a query costs ~1-3 ms of Bolt round trip against < 1 ms of
execution for a room's objects (PROFILE, 100 objects per room), so a room-scoped answer sends
as few as it can: the room is looked up once (while parsing), its candidates are read once with
the provenance fields (`_candidates`, shared by the count, the size filter and `_provenance`),
and the "show me" templates bring the winner's thumbnail along.

Across rooms one physical object may be stored once per room that saw it, linked by
SAME_AS; counts over more than one room count each SAME_AS group once (`_same_as_excess`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional, Sequence, Union, cast

from sg3d.core.stored import Row
from sg3d.core.errors import Sg3dError
from sg3d.core.relation_rules import SYMMETRIC, VIEWPOINT
from sg3d.graphdb import cypher
from sg3d.queries import compose
from sg3d.queries import viewpoint as views
from sg3d.queries.answer.parts import AnswerObject, Provenance, TemplateStep
from sg3d.queries.answer.operations import row_value
from sg3d.queries.logic import ChangeQuery, Form, Query
from sg3d.queries.reader.typos import typo_nouns, typo_vocabulary
from sg3d.queries.naming import names_in_store
from sg3d.queries.scoping import by_size, few_rooms
from sg3d.queries.sets import same_as_roots
from sg3d.queries.vocabulary import (
    ABSENT,
    IMPLIED_BY,
    LIST_SHOWN,
    MAX_QUESTION,
    PROVENANCE_MAX,
    REL_WORDS,
    ROW_LIMIT,
    refusal,
)
from sg3d.queries.answer.wording import plural, the, without_place

CHANGE_OPS = ("changes", "gone", "before")      # answered from the scans' history (sg3d/app/changes.py)
# how a reading is answered, as --explain says it
PLANS = {"templates": "per-form templates (index-aware variants), the query below",
         "sets": "scene read (vqa_scene_objects, vqa_scene_relations) + set operations",
         "history": "the scans' history (sg3d/app/changes.py)"}


@dataclass
class Answer:
    question: str
    ok: bool
    text: str                                   # the one-line answer (or the refusal)
    form: str = "refused"                       # count | exists | list | attribute | show | refused
    value: Any = None                           # int (count), bool (exists), list / dict / str
    objects: list[AnswerObject] = field(default_factory=list)
    query: Optional[Query] = None
    steps: list[TemplateStep] = field(default_factory=list)   # for --explain
    thumbnail: Optional[bytes] = None
    # the objects the answer rests on: id, name, label, score, observations, n_frames, last seen
    provenance: list[Provenance] = field(default_factory=list)
    logical: Optional[dict] = None          # the logical form the grammar read (sg3d/queries/logic.py)
    # no object of an asked kind is in scope: the answer says it was not found, not that none is
    absent_evidence: bool = False
    plan: Optional[str] = None              # how the reading was answered (--explain): see PLANS
    # a question about re-scans, as read: the application answers it from the scans' history
    # (sg3d/app/ask.py dispatches on it); until then this answer is a refusal saying so
    change: Optional["ChangeAsked"] = None

    def to_json(self) -> dict:
        return {"question": self.question, "ok": self.ok, "form": self.form, "answer": self.text,
                "value": self.value, "objects": self.objects, "logical_form": self.logical,
                "absent_evidence": self.absent_evidence, "plan": self.plan,
                "query": self.query.summary() if self.query else None, "steps": self.steps,
                "templates": [s["template"] for s in self.steps], "provenance": self.provenance,
                "thumbnail_bytes": len(self.thumbnail) if self.thumbnail else None}

    def explain_lines(self) -> list[str]:
        """What --explain prints: the reading of the question, templates, parameters, and the
        objects the answer rests on (ids only here and in --json)."""
        import json

        out = []
        if self.logical is not None:
            out.append(f"logical form: {json.dumps(self.logical)}")
        if self.plan is not None:
            out.append(f"plan: {PLANS.get(self.plan, self.plan)}")
        if self.query is not None:
            out.append(f"form: {json.dumps(self.query.summary())}")
            out += [f"read as: {m}" for m in self.query.mappings()]
            if self.query.ignored:
                out.append(f"ignored: {', '.join(self.query.ignored)}")
        for step in self.steps:
            out.append(f"template: {step['template']}" + (f" [{step['rel_type']}]" if step.get("rel_type") else "")
                       + f" params: {json.dumps(step['params'], default=str)}")
        for p in self.provenance:
            out.append(f"rests on: {p['name']} = {p['id']} (score {p.get('score')}, "
                       f"{p.get('observations')} observations, {p.get('n_frames')} frames, "
                       f"frames {p.get('first_frame')}-{p.get('last_frame')}, last seen {p.get('last_seen')})")
        return out


@dataclass(frozen=True)
class ChangeAsked:
    """A change question (changes | gone | before) as the reader read it: its form, and the text
    it read (refusals name the words as typed, `own_words`)."""

    form: Form
    phrased: str


class Refusal(Sg3dError):
    pass


# -- plumbing ------------------------------------------------------------------------------------
class _Run:
    """Runs templates read-only and records them for --explain."""

    def __init__(self, store, viewpoint=None, seen_from: Optional[str] = None):
        self.store = store
        self.steps: list[TemplateStep] = []
        self.viewpoint, self.seen_from = viewpoint, seen_from     # see sg3d/queries/viewpoint.py
        self._names: dict[str, str] = {}
        self.notes: list[str] = []                 # what the answer must say it did (main colour)
        # one answer reads its candidates once: the count, then its provenance, reuse them
        self.candidates: dict[tuple, list[Row]] = {}
        self.rows_by_id: dict[str, dict] = {}      # candidate rows that carry provenance fields

    def names(self, rows) -> dict[str, str]:
        """id -> readable name (sg3d/queries/naming.py) for stored objects (rows with id, label, room)."""
        missing = [r for r in rows if r.get("id") and r["id"] not in self._names]
        if missing:
            self._names.update(names_in_store(self.read, missing))
        return self._names

    def read(self, name: str, **params) -> list[Row]:
        self.steps.append({"template": f"cypher/{name}.cypher", "params": params})
        return self.store.read(name, **params)

    def read_rel(self, name: str, rel_type: Union[str, Sequence[str]], **params) -> list[Row]:
        if not isinstance(rel_type, str):
            # several types ("near" = NEAR or NEXT_TO): one run each, rows in order
            return [r for t in rel_type for r in self.read_rel(name, t, **params)]
        text = cypher.render(name, rel_type)   # whitelisted type only, or ValueError
        self.steps.append({"template": f"cypher/{name}.cypher", "rel_type": rel_type, "params": params})
        with self.store.session() as s:
            return s.execute_read(lambda tx: tx.run(text, params).data())


def _what(q: Query, n: int) -> str:
    t = q.target
    bits = [b for b in (q.size, q.colour) if b]
    noun = "objects" if t.labels is None else (plural(t.names[0], n) if len(t.names) == 1 else
                                               " or ".join(plural(x, n) for x in t.names))
    if t.labels is None and n == 1:
        noun = "object"
    return " ".join(bits + [noun])


def _a(noun: str) -> str:
    """The noun with its indefinite article: "a chair", "an orange cup"."""
    return f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun}"


def _where(q: Query, rooms_asked: bool) -> str:
    out = ""
    if q.relation:
        colour = f"{q.anchor_colour} " if q.anchor_colour else ""
        said = f"{colour}{' or '.join(q.anchor_target().names)}"
        article = "an" if q.anchor_article == "a" and said[:1] in "aeiou" else q.anchor_article
        out += f" {q.relation_word} {article} {said}"
    if q.room:
        out += f" in the {q.room}"
    return out


def _understood(q: Query, extra: Optional[list] = None) -> str:
    notes = list(extra or [])
    for t in (q.target, q.anchor):
        if t is not None and t.how == "unknown":
            notes.append(f"'{t.names[0]}' is not among the categories the detector stores")
        if t is not None and t.how == "embedding":
            notes.append(f"'{t.phrase}' read as {' + '.join(t.names)} (similarity {t.similarity:.2f})")
        if t is not None and t.how == "either":
            notes.append(f"'{t.phrase}' names {len(t.names)} categories; counted together: {' and '.join(t.names)}")
    if q.ignored:
        notes.append("ignored: " + ", ".join(q.ignored))
    return f" [{'; '.join(notes)}]" if notes else ""


def _variant(base: str, rooms, labels=()) -> str:
    """Which variant of a template: see the module docstring (access paths)."""
    if few_rooms(rooms):
        return base + "_in_rooms"
    return base + "_any" if labels is None else base


def _rooms_named(store, name: str, building: Optional[str]) -> list[Row]:
    """Rooms called `name` (any case): the room_name index for the usual spellings, and only
    when none matches the case-insensitive scan of every room."""
    b = building.lower() if building else None
    spellings = sorted({name, name.lower(), name.title(), name.capitalize(), name.upper()})
    rows = store.read("vqa_room_named", names=spellings, building=b)
    return rows or store.read("vqa_rooms", room=name.lower(), building=b) or _rooms_like(store, name, building)


def _building_like(run: _Run, building: str) -> list[Row]:
    """The rooms of the one building `building` means (spaces, case, a small typo); the answer
    says what was matched."""
    from sg3d.queries.place_names import match_name, read_as

    rows = run.read("vqa_room_names", building=None)
    hit = match_name(building, {r["building"] for r in rows}, typo_vocabulary())
    said = read_as(building, hit, "building") if hit else None
    if said and said not in run.notes:
        run.notes.append(said)
    return [r for r in rows if hit is not None and r["building"] == hit]


def _rooms_like(store, name: str, building: Optional[str]) -> list[Row]:
    """Rooms whose name (and building) `name` means once spaces, case and a small typo are set
    aside (sg3d/queries/place_names.py): "living room" -> `livingroom`; each row carries
    `read_as`, the note the answer gives. [] when no one room is meant."""
    from sg3d.queries.place_names import match_name, read_as

    rows = store.read("vqa_room_names", building=None)
    vocab = typo_vocabulary()
    notes = []
    if building:
        b = match_name(building, {r["building"] for r in rows}, vocab)
        if b is None:
            return []
        rows = [r for r in rows if r["building"] == b]
        notes.append(read_as(building, b, "building"))
    hit = match_name(name, {r["name"] for r in rows}, vocab)
    if hit is None:
        return []
    note = "; ".join(n for n in notes + [read_as(name, hit)] if n)
    return [{**r, "read_as": note} for r in rows if r["name"] == hit]


def _scope(run: _Run, room: Optional[str], building: Optional[str],
           known: Optional[dict] = None) -> Optional[list[str]]:
    """Room ids in scope, None = everything; `known`: rooms already looked up by name while
    parsing (same building)."""
    if room is None and building is None:
        return None
    if room is not None:
        run.steps.append({"template": "cypher/vqa_room_named.cypher", "params": {"names": [room], "building": building}})
        rows = (known or {}).get(room)
        if rows is None:
            rows = _rooms_named(run.store, room, building)
        said = rows[0].get("read_as") if rows else None
        if said and said not in run.notes:
            run.notes.append(said)
    elif building is not None:
        rows = run.read("vqa_rooms", room=None, building=building.lower()) or _building_like(run, building)
    if not rows:
        stored = sorted({f"{r['building']}/{r['name']}" for r in run.store.read("vqa_rooms", room=None, building=None)})
        if not stored:
            raise Refusal("the store holds no scene graph yet: build one first (sg3d build ...)")
        what = " in ".join(x for x in (f"room '{room}'" if room else "", f"building '{building}'" if building else "") if x)
        raise Refusal(f"no {what} in the store (rooms: {', '.join(stored) or 'none'})")
    return [r["id"] for r in rows]


def _filters(q: Query, rooms) -> dict:
    return {"labels": q.target.labels, "rooms": rooms, "colour": q.colour}


def asked_types(relation: str) -> tuple[str, ...]:
    """The stored relation types that answer a question about `relation`: itself, and the more
    specific types that imply it (IMPLIED_BY: NEXT_TO implies NEAR)."""
    return IMPLIED_BY.get(relation, (relation,))


def _candidates(run: _Run, q: Query, rooms) -> list[Row]:
    """The objects the question is about (target, attributes, relation), one row per object;
    read once per answer (the count and its provenance share them)."""
    key = (id(q), tuple(rooms) if rooms is not None else None)
    if key not in run.candidates:
        rows = _read_candidates(run, q, rooms)
        run.candidates[key] = rows
        run.rows_by_id.update((r["id"], r) for r in rows if r.get("id") and "observations" in r)
    return run.candidates[key]


def _read_candidates(run: _Run, q: Query, rooms) -> list[Row]:
    if q.relation in VIEWPOINT:      # never stored: computed from a viewpoint (sg3d/queries/viewpoint.py)
        try:
            return by_size(run, views.related(run, q, rooms, run.viewpoint, run.seen_from), q.size)
        except ValueError as exc:
            raise Refusal(str(exc)) from None
    if q.relation:
        name = _variant("vqa_related_any" if q.symmetric else "vqa_related", rooms)
        rows = run.read_rel(name, asked_types(q.relation), anchors=q.anchor_target().labels,
                            anchor_colour=q.anchor_colour,
                            limit=ROW_LIMIT, **_filters(q, rooms))
        seen, unique = set(), []
        for r in rows:
            if r["id"] not in seen:
                seen.add(r["id"])
                unique.append(r)
        rows = unique
    else:
        rows = run.read(_variant("vqa_objects", rooms, q.target.labels), limit=ROW_LIMIT, **_filters(q, rooms))
        rows = _main_colour(run, q, rows)
    return by_size(run, rows, q.size)


def _main_colour(run: _Run, q: Query, rows: list[Row]) -> list[Row]:
    """A colour word means the main colour: rows that have it as their second colour only are
    left out, and the answer says how many (run.notes)."""
    if q.colour is None:
        return rows
    second = [r for r in rows if r.get("colour") != q.colour]
    if second:
        noun = plural(second[0]["label"], len(second)) if len({r["label"] for r in second}) == 1 else \
            ("object" if len(second) == 1 else "objects")
        run.notes.append(f"by main colour; {len(second)} more {noun} {'has' if len(second) == 1 else 'have'} "
                         f"{q.colour} as a second colour")
    return [r for r in rows if r.get("colour") == q.colour]


def _brief(r: dict) -> AnswerObject:
    out = cast(AnswerObject, {k: r.get(k) for k in ("id", "label", "colour", "volume", "room") if r.get(k) is not None})
    for k in ("anchor_id", "anchor_label", "distance"):
        if r.get(k) is not None:
            out[k] = r[k]
    return out


# -- one function per query form ---------------------------------------------------------------
def count(run: _Run, q: Query, rooms) -> Answer:
    """Simple, hierarchical, attribute and relation counting."""
    breakdown: dict[str, int] = {}
    if q.relation or q.size or few_rooms(rooms):
        # a few rooms: their objects are read anyway for the provenance, so count those rows
        # (one query instead of a count and then the objects)
        rows = _candidates(run, q, rooms)
        for r in rows:
            breakdown[r["label"]] = breakdown.get(r["label"], 0) + 1
    if not (q.relation or q.size) and (not few_rooms(rooms) or len(rows) >= ROW_LIMIT):
        name = _variant("vqa_count", rooms, q.target.labels)
        breakdown = {r["label"]: r["n"] for r in run.read(name, **_filters(q, rooms))}
    merged = 0
    if rooms is None or len(rooms) > 1:
        for label, extra in _same_as_excess(run, q, rooms).items():
            if label in breakdown:
                breakdown[label] -= extra
                merged += extra
    n = sum(breakdown.values())
    text = f"{n} {_what(q, n)}{_where(q, rooms is not None)}"
    if len(breakdown) > 1 or (q.target.how in ("group", "any") and breakdown):
        text += " (" + ", ".join(f"{v} {k}" for k, v in sorted(breakdown.items(), key=lambda kv: (-kv[1], kv[0]))) + ")"
    if merged:
        text += f" [{merged} seen from two rooms counted once]"
    return Answer(q.target.phrase, True, text, "count", n, query=q, objects=[{"label": k, "n": v} for k, v in breakdown.items()])


def exists(run: _Run, q: Query, rooms) -> Answer:
    a = count(run, q, rooms)
    n = a.value
    if n == 0:
        text = f"no, I have not found {_a(_what(q, 1))}{_where(q, rooms is not None)}"
    else:
        text = f"yes, {n} {_what(q, n)}{_where(q, rooms is not None)}"
    return Answer("", True, text, "exists", n > 0, a.objects, q)


def list_objects(run: _Run, q: Query, rooms) -> Answer:
    rows = _candidates(run, q, rooms)
    shown = rows[:LIST_SHOWN]
    named = run.names(shown)
    names = ", ".join(named[r["id"]] for r in sorted(shown, key=lambda r: named[r["id"]]))
    more = f", ... {len(rows) - len(shown)} more" if len(rows) > len(shown) else ""
    head = f"{len(rows)} {_what(q, len(rows))}{_where(q, rooms is not None)}"
    text = f"{head}: {names}{more}" if rows else f"none: no {_what(q, 1)}{_where(q, rooms is not None)}"
    return Answer("", True, text, "list", [_brief(r) for r in rows], [_brief(r) for r in rows], q)


def attribute(run: _Run, q: Query, rooms) -> Answer:
    """What colour / how big is the <object>: one value per matching object."""
    rows = _candidates(run, q, rooms)
    if not rows:
        return Answer("", True, f"I have not found {_a(_what(q, 1))}{_where(q, rooms is not None)}", "attribute", None,
                      query=q)
    if q.attribute == "colour":
        values = [r.get("colour") or "unknown" for r in rows]
    else:
        values = ["x".join(f"{v:.2f}" for v in r["size"]) + " m" if r.get("size") else "unknown" for r in rows]
    noun = _what(q, len(rows))
    if len(rows) == 1:
        text = f"the {noun} is {values[0]}" if q.attribute == "colour" else f"the {noun} is {values[0]} (w x d x h)"
    else:
        named = run.names(rows[:LIST_SHOWN])
        text = f"{len(rows)} {noun}: " + ", ".join(f"{named[r['id']]}: {v}" for r, v in list(zip(rows, values))[:LIST_SHOWN])
    return Answer("", True, text, "attribute", values if len(values) > 1 else values[0], [_brief(r) for r in rows], q)


def show(run: _Run, q: Query, rooms) -> Answer:
    """The multimodal answer: the biggest/smallest/closest object and its thumbnail."""
    if q.superlative == "closest":
        rows = run.read(_variant("vqa_closest", rooms), anchors=q.anchor_target().labels, **_filters(q, rooms))
        how = f"closest to the {' or '.join(q.anchor_target().names)}"
    else:
        if q.size:
            raise Refusal("'big'/'small' together with a superlative is not supported")
        sign = 1 if q.superlative == "max" else -1
        if q.relation:
            # only the objects related to the anchor compete ("the biggest cup on the table")
            rows = sorted((r for r in _candidates(run, q, rooms) if r.get("volume") is not None),
                          key=lambda r: (-sign * float(r["volume"]), r["id"]))[:1]
        else:
            rows = run.read(_variant("vqa_extreme", rooms, q.target.labels), sign=sign, **_filters(q, rooms))
            run.rows_by_id.update((r["id"], r) for r in rows if "observations" in r)
        how = "biggest" if q.superlative == "max" else "smallest"
    rel = f" {q.relation_word} the {' or '.join(q.anchor_target().names)}" if q.relation else ""
    if not rows:
        return Answer("", True, f"I have not found {_a(_what(q, 1))}{rel}{' in the ' + q.room if q.room else ''}",
                      "show", None, query=q)
    r = rows[0]
    if "thumbnail" in r:       # the extreme templates bring the winner's thumbnail along
        data = r["thumbnail"]
    else:
        thumb = run.read("vqa_thumbnail", id=r["id"])
        data = thumb[0]["thumbnail"] if thumb else None
    detail = f"{r.get('volume', 0) or 0:.3g} m^3" if q.superlative != "closest" else f"{r['distance']:.2f} m away"
    named = the(run.names([r])[r["id"]])
    if q.superlative == "closest":
        text = f"the {_what(q, 1)} {how}: {named} ({detail})"
    else:
        text = f"the {how} {_what(q, 1)}{rel}: {named} ({detail})"
    return Answer("", True, text, "show", _brief(r), [_brief(r)], q, thumbnail=bytes(data) if data else None)


def rooms_with(run: _Run, q: Query, rooms) -> Answer:
    """Which rooms hold at least one matching object; the total counts each SAME_AS group once."""
    rows = _candidates(run, q, rooms)
    walked = {w["id"]: w for w in run.read("places_rooms_of", ids=[r["id"] for r in rows])} if rows else {}
    per_room: dict[tuple[str, str], int] = {}
    for r in rows:
        # a walk split into rooms (`sg3d build --rooms auto`): the room found in it, then the recording
        key = (r["room"], walked[r["id"]]["name"] if r["id"] in walked else "")
        per_room[key] = per_room.get(key, 0) + 1
    if not per_room:
        return Answer("", True, f"none: no room holds a {_what(q, 1)}{_where(q, False)}", "rooms", [], query=q)
    extra = sum(_same_as_excess(run, q, rooms).values()) if len({rid for rid, _ in per_room}) > 1 else 0
    n = len(rows) - extra
    said = {key: found_room(walked[r["id"]]) for r in rows if r["id"] in walked
            for key in [(r["room"], walked[r["id"]]["name"])]}
    names = ", ".join(f"{said.get(key, '')}{key[0].split('/', 1)[-1]} ({k} {_what(q, k)})"
                      for key, k in sorted(per_room.items()))
    text = f"{names}; {n} {_what(q, n)} in all"
    if extra:
        text += f" [{extra} seen from two rooms counted once]"
    value: list[AnswerObject] = []
    for (rid, found), k in sorted(per_room.items()):
        value.append({"room": rid, "n": k, "found_room": found} if found else {"room": rid, "n": k})
    return Answer("", True, text, "rooms", value, value, q)


def found_room(w: Optional[dict]) -> str:
    """The words for the room of the walk an object is in (`sg3d build --rooms auto`), said before
    the recorded room: "room 2 (looks like a kitchen: refrigerator, sink) of the "; "" without one."""
    if not w:
        return ""
    kind = f" (looks like {_a(w['kind_guess'])}: {', '.join(w['kind_evidence'])})" if w.get("kind_guess") else ""
    return f"{w['name']}{kind} of the "


def where(run: _Run, q: Query, rooms) -> Answer:
    """Where is the <object>: per matching object, what it is on/in/next to, and its room."""
    rows = _candidates(run, q, rooms)
    if not rows:
        return Answer("", True, f"I have not found {_a(_what(q, 1))}{_where(q, rooms is not None)}", "where", [],
                      query=q)
    ids = [r["id"] for r in rows[:LIST_SHOWN]]
    rels: dict[str, list[Row]] = {i: [] for i in ids}
    placed: dict[str, list[Row]] = {i: [] for i in ids}    # with colour and score, for the sentence
    # an edge of a directed type is said only when it leaves the object (the cabinet is never
    # "on" the vase that stands on it); symmetric ones from either end
    for incoming, types in ((False, sorted(REL_WORDS)), (True, sorted(SYMMETRIC))):
        for e in run.read("vqa_where", ids=ids, types=types, incoming=incoming):
            if not any(x["other_id"] == e["other_id"] and x["rel"] == e["rel"] for x in rels[e["id"]]):
                rels[e["id"]].append({"rel": e["rel"], "other_id": e["other_id"], "other_label": e["other_label"]})
                placed[e["id"]].append(dict(e))
    value: list[AnswerObject] = []
    parts = []
    named = run.names(rows[:LIST_SHOWN] + [{"id": x["other_id"], "label": x["other_label"], "room": r.get("room")}
                                           for r in rows[:LIST_SHOWN] for x in rels[r["id"]]])
    walked = {w["id"]: w for w in run.read("places_rooms_of", ids=ids)}
    for r in rows[:LIST_SHOWN]:
        found = rels[r["id"]]
        room = found_room(walked.get(r["id"])) + (r.get("room") or "?").split("/", 1)[-1]
        said = views.describe_place(placed[r["id"]], {k: the(v) for k, v in named.items()})
        parts.append(f"{the(without_place(named[r['id']], said))} is "
                     + (f"{said}, in the {room}" if said else f"in the {room}"))
        value.append({**_brief(r), "relations": found})
    more = f"; ... {len(rows) - LIST_SHOWN} more" if len(rows) > LIST_SHOWN else ""
    return Answer("", True, "; ".join(parts) + more, "where", value, value, q)


FORMS = {"where": where, "rooms": rooms_with, "count": count, "exists": exists, "list": list_objects, "attribute": attribute, "show": show}


def answer(store, question: str, room: Optional[str] = None, building: Optional[str] = None,
           embedding=None, use_embedding: bool = True, viewpoint=None) -> Answer:
    """Answer one question from the stored scene graph (read-only, except the taxonomy load).
    `viewpoint`: where "in front of / behind / left of / right of" are seen from (a camera pose,
    a point or an object; sg3d/queries/viewpoint.py), unless the question says "as seen from the X".
    A question about re-scans is refused here, its reading in `Answer.change` for the application
    to answer from the history of scans."""
    if len(question) > MAX_QUESTION:
        return Answer(question[:60] + "...", False,
                      f"the question is {len(question)} characters long; ask in at most {MAX_QUESTION}")
    from sg3d.queries.reader.grammar import GrammarError

    try:
        phrased, notes = _phrase(store, question, building)
    except GrammarError as exc:     # the pre-pass failed (ReaderFailure): refused naming the word
        return Answer(question, False, refusal(compose.grammar_refusal(question, exc).text, question))
    if not phrased:
        return Answer(question, False, refusal("empty question", question))
    a = _answer(store, question, phrased, notes, room, building, embedding, use_embedding, viewpoint)
    if not a.ok:
        a.text = own_words(question, phrased, a.text)
    return a


def own_words(question: str, phrased: str, text: str) -> str:
    """A refusal names the words the user typed: a quoted word that a rewrite or a typo fix put
    in ("except" for "apart from", "what" for "waht") is said as typed (the example after
    "try e.g." is left alone)."""
    import re

    from sg3d.queries.reader.tidy import said_word

    head, sep, tail = text.partition("; try e.g.")
    typed = {w.strip(".'") for w in re.sub(r"[^\w'. -]+", " ", question.lower()).split()}

    def mapped(m: "re.Match[str]") -> str:
        words = m.group(1).split()
        if all(w in typed for w in words):
            return m.group(0)
        out: list[str] = []
        for w in words:
            said = w if w in typed else said_word(question, phrased, w)
            if not out or out[-1] != said:
                out.append(said)
        return f"'{' '.join(out)}'"

    return re.sub(r"(?<!\w)'([^']+)'(?!\w)", mapped, head) + sep + tail


def _answer(store, question: str, phrased: str, notes: list[str], room, building, embedding, use_embedding,
            viewpoint) -> Answer:
    from sg3d.queries.reader.grammar import GrammarError

    from sg3d.queries.reader.reading import GrammarReader, StoredRooms, room_lookup

    run = _Run(store, viewpoint)
    # one indexed look-up per candidate name, not a read of every room (1,000 rooms: 10 ms)
    rooms = StoredRooms(lambda: _room_names(store, building), lambda name: _rooms_named(store, name, building),
                        run.notes)
    try:       # the one reading of the question
        form = GrammarReader().read(phrased, rooms)
    except GrammarError as exc:
        o = compose.grammar_refusal(phrased, exc)
        return Answer(question, False, refusal(o.text, question) if o.kind == "unread" else o.text)
    if form.op in CHANGE_OPS:
        return Answer(question, False, "questions about re-scans are answered by `sg3d ask` (the scans' history)",
                      form="changes", logical=form.form(), change=ChangeAsked(form, phrased))
    run.seen_from = form.seen_from.text() if form.seen_from is not None else None
    form = compose.planned(form)
    ev = compose.Evaluator(run, room_lookup(form, rooms.rows), embedding, use_embedding, building)
    try:       # one plan, run by the executor it names
        p = compose.plan(ev, form, room, lambda name: _scope(run, name, building, rooms.seen))
        outcome = compose.run_sets(p, room) if isinstance(p, compose.Plan) and p.executor == "sets" else p
    except Refusal as exc:
        return Answer(question, False, str(exc), steps=run.steps, logical=form.form())
    if isinstance(outcome, compose.Plan):
        return _planned(question, outcome, run, (room, building), rooms.seen, notes)
    if outcome.kind == "answer":
        return _in_unit(_composed(question, outcome, notes, run), question)
    return Answer(question, False, refusal(outcome.text, question) if outcome.kind == "unread"
                  else outcome.text, logical=outcome.form, steps=run.steps)


def _planned(question: str, p: compose.Plan, run: _Run, scope: tuple, seen, notes: list[str]) -> Answer:
    """A simple form's plan run on the per-form templates (index-aware variants); `scope`: the
    (room, building) asked in."""
    room, building = scope
    q = p.query
    assert q is not None
    store = run.store
    if q.target.how == "group" or (q.anchor is not None and q.anchor.how == "group"):
        _expand_groups(store, q)
    try:
        if p.room_ids is not None:       # the room the question names, looked up while reading
            run.steps.insert(0, {"template": "cypher/vqa_room_named.cypher",
                                 "params": {"names": [q.room], "building": building}})
        rooms = p.room_ids if p.room_ids is not None else _scope(run, room, building, seen)
        result = FORMS[q.form](run, q, rooms)
    except Refusal as exc:
        return Answer(question, False, str(exc), query=q, steps=run.steps, logical=p.logical)
    if _nothing(result) and not run.read("object_total")[0]["n"]:
        return Answer(question, False, "the store holds no scene graph yet: build one first (sg3d build ...)",
                      query=q, steps=run.steps)
    result.question, result.query, result.logical, result.plan = question, q, p.logical, "templates"
    _honest_absence(run, result, q, rooms)
    result.provenance = _provenance(run, result, q, rooms)
    result.steps = run.steps
    result.text += _understood(q, notes + run.notes + _which(q, result))
    return result


def _which(q: Query, a: Answer) -> list[str]:
    """"where is the cup" when three cups match: the answer gives each and asks which was meant."""
    many = [o for o in a.objects if isinstance(o, dict) and o.get("id") and not o.get("could_be")]
    if not q.one or q.form not in ("where", "attribute") or len(many) < 2:
        return []
    noun = q.target.names[0] if len(q.target.names) == 1 else "object"
    return [f"{len(many)} {plural(noun, len(many))} match 'the {noun}': which one did you mean?"]


def change_query(form: Form, embedding=None) -> ChangeQuery:
    """A change form (changes | gone | before) as the scans' history reads it; Refusal naming the
    object words it cannot place."""
    from sg3d.queries.lexicon import resolve

    nps = list(form.sets)
    filters = list(form.filters) + [f for np in nps for f in np.filters]
    room = next((" ".join(f.other.words) for f in filters if f.kind == "rel" and f.relation in ("in", "inside")), None)
    if form.op != "before":
        return ChangeQuery(form.op, room=room)
    words = " ".join(w for np in nps for w in np.words)
    target, why = resolve(words, embedding=embedding)
    if target is None or not target.labels:
        raise Refusal(why or f"I don't know what '{words}' is")
    return ChangeQuery("before", target=target, room=room)


def history_refusal(question: str, asked: ChangeAsked, refused: Refusal) -> Answer:
    """A change question whose objects cannot be placed (`change_query`'s Refusal), refused."""
    return Answer(question, False, str(refused), form="changes", logical=asked.form.form())


def _phrase(store, text: str, building: Optional[str]) -> tuple[str, list[str]]:
    """Frames, apostrophes, numbers and typos (sg3d/queries/reader); room names are never
    read as typos (they are looked up only when a word is outside the vocabulary)."""
    from sg3d.queries.reader.tidy import tidy
    from sg3d.queries.reader.typos import fix_typos, is_word

    try:
        tidied = tidy(text)
    except Exception as exc:        # a rewrite that fails is a refusal, never a traceback
        raise _reader_failed(text, "tidy", exc) from None
    asides = [f"ignored: {', '.join(tidied.dropped)}"] if tidied.dropped else []
    asides += tidied.notes
    vocab = typo_vocabulary()
    if all(is_word(w, vocab) for w in tidied.text.split()):
        return tidied.text, asides
    rooms = {w for n in _room_names(store, building, with_buildings=True) for w in n.lower().split()}
    try:
        fixed, notes = fix_typos(tidied.text, vocab, rooms, typo_nouns())
    except Exception as exc:        # the same for the typo fixer
        raise _reader_failed(tidied.text, "fix_typos", exc) from None
    return fixed, asides + notes


def _reader_failed(text: str, step: str, exc: Exception):
    """A failure of the phrasing pre-pass (`step`) on `text`, logged with its traceback, as the
    grammar's ReaderFailure naming the first word (the pre-pass reads the whole text at once)."""
    import logging

    from sg3d.queries.reader.grammar import ReaderFailure

    word = next(iter(text.split()), None)
    logging.getLogger("sg3d.queries").warning("the question reader (%s) failed on %r: %s: %s", step, text,
                                              exc.__class__.__name__, exc, exc_info=(type(exc), exc, exc.__traceback__))
    return ReaderFailure(f"the question reader stopped at '{word}' ({step})", word)


def _room_names(store, building: Optional[str], with_buildings: bool = False) -> list[str]:
    """The names a question may call a room by: the recorded rooms', and the names and guessed
    kinds of the rooms found in their walks ("room 2", "living room"; sg3d/queries/walk.py)."""
    b = building.lower() if building else None
    rows = store.read("vqa_room_names", building=b)
    walked = store.read("vqa_walk_room_names", building=b) if rows else []
    found = sorted({w["name"] for w in walked} | {w["kind_guess"] for w in walked if w.get("kind_guess")})
    return [r["name"] for r in rows] + found + ([r["building"] for r in rows] if with_buildings else [])


def _in_unit(a: Answer, question: str) -> Answer:
    """A distance asked in a unit ("how far ... in centimetres") says it in that unit too."""
    from sg3d.queries.reader.tidy import asked_unit
    from sg3d.queries.vocabulary import UNIT_M

    unit = asked_unit(question)
    if unit is None or unit == "m" or a.form != "distance" or not isinstance(a.value, float):
        return a
    said = f"{a.value:.2f} m"
    a.text = a.text.replace(said, f"{said} ({a.value / UNIT_M[unit]:.0f} {unit})", 1)
    return a


def _composed(question: str, o, notes: list[str], run: _Run) -> Answer:
    """An answer of the compiler (sg3d/queries/compose.py) as an Answer."""
    extra = notes + [n for n in run.notes if n not in notes + o.notes] + o.notes
    text = o.text + (f" [{'; '.join(extra)}]" if extra else "")
    named = run.names(o.rows[:PROVENANCE_MAX]) if o.rows else {}     # one read for every row, not one each
    objects = [cast(AnswerObject, row_value(r, named.get(r["id"], r["label"]))) for r in o.rows[:PROVENANCE_MAX]]
    a = Answer(question, True, text, o.op, o.value, objects, steps=run.steps, logical=o.form,
               absent_evidence=o.absent, thumbnail=bytes(o.thumbnail) if o.thumbnail else None, plan="sets")
    ids = [r["id"] for r in o.rows[:PROVENANCE_MAX]]
    a.provenance = [{"id": i, "name": run.names([run.rows_by_id[i]]).get(i), "label": run.rows_by_id[i]["label"],
                     "room": run.rows_by_id[i].get("room"), "score": run.rows_by_id[i].get("score"),
                     "observations": run.rows_by_id[i].get("observations"),
                     "n_frames": run.rows_by_id[i].get("n_frames"),
                     "first_frame": run.rows_by_id[i].get("first_frame"),
                     "last_frame": run.rows_by_id[i].get("last_frame"),
                     "last_seen": _when(run.rows_by_id[i]["updated_at"]) if run.rows_by_id[i].get("updated_at") else None}
                    for i in ids if i in run.rows_by_id]
    return a


ABSENT_FORMS = ("count", "exists", "where", "list", "attribute", "show", "rooms")


def _honest_absence(run: _Run, a: Answer, q: Query, rooms) -> None:
    """No object of an asked kind (the object asked about, or the one it is related to) in
    scope at all: say it was not found (small or uncommon things may be missed), never that
    there is none; --json carries absent_evidence."""
    if not a.ok or a.form not in ABSENT_FORMS or not _nothing(a):
        return
    name = "vqa_scene_objects_in_rooms" if few_rooms(rooms) else "vqa_scene_objects"
    for t in (q.target, q.anchor):
        if t is None or t.labels is None:
            continue
        if t.labels and run.read(name, rooms=rooms, labels=t.labels, limit=1):
            continue
        what = " or ".join(t.names) or t.phrase
        article = "an" if what[:1] in "aeiou" else "a"
        place = f" in the {q.room}" if q.room else ""
        a.text = f"I have not found {article} {what}{place} ({ABSENT})"
        a.absent_evidence = True
        if t is q.target:
            _could_be(run, a, q, rooms, place)
        return


def _could_be(run: _Run, a: Answer, q: Query, rooms, place: str) -> None:
    """None of the asked kind is named: "is there", "how many" and "where is" list the unnamed
    objects that could be one (sg3d/queries/unnamed.py), said as unnamed; the objects stay so.
    The value stays what was named (False, 0, []), with absent_evidence, as for any absence."""
    from sg3d.queries import unnamed

    t = q.target
    labels = t.labels or []
    if a.form not in ("exists", "count", "where", "rooms") or q.anchor is not None or q.size or len(labels) != 1 \
            or len(t.names) != 1:
        return
    found = unnamed.candidates(run, labels[0], rooms, q.colour)
    if not found:
        return
    what = " ".join(x for x in (q.colour, t.names[0]) if x)
    if a.form == "count":
        a.text = unnamed.none_named(plural(what), place, found)
    else:
        a.text = unnamed.not_named(what, place, found)
    if a.form == "rooms":       # "which room is the fridge in": the room of each thing that could be one
        walked = {w["id"]: w for w in run.read("places_rooms_of", ids=[o["id"] for o in found[:LIST_SHOWN]])}
        said = [f"the {found_room(walked.get(o['id']))}{(o.get('room') or '?').split('/', 1)[-1]}"
                for o in found[:LIST_SHOWN]]
        a.text += f"; it is in {said[0]}" if len(said) == 1 else f"; they are in {', '.join(said)} (in that order)"
    a.objects = [cast(AnswerObject, {**_brief(o), "shape": o.get("shape"), "size": o.get("size"),
                                     "support": o["support"], "could_be": o["could_be"]}) for o in found[:LIST_SHOWN]]


def _nothing(a: Answer) -> bool:
    return a.value in (0, False, None, [], {})


def _provenance(run: _Run, a: Answer, q: Query, rooms) -> list[Provenance]:
    """The objects an answer rests on, each with its name and how sure the store is of it:
    score (detector), observations (merged detections), n_frames, the frames that saw it and
    when it was last updated. A count fetches its objects only when there are few."""
    ids = [o["id"] for o in a.objects if isinstance(o, dict) and o.get("id")]
    if not ids and a.form in ("count", "exists") and a.value and isinstance(a.value, (int, bool)) \
            and int(a.value) <= PROVENANCE_MAX and q.target.labels != []:
        ids = [r["id"] for r in _candidates(run, q, rooms)]
    ids = list(dict.fromkeys(ids))[:PROVENANCE_MAX]
    if not ids:
        return []
    if all(i in run.rows_by_id for i in ids):     # the candidate rows already say it
        rows = [run.rows_by_id[i] for i in sorted(ids)]
    else:
        rows = run.read("vqa_provenance", ids=ids)
    names = run.names(rows)
    out: list[Provenance] = []
    for r in rows:
        seen = r.get("updated_at")
        out.append({"id": r["id"], "name": names.get(r["id"], r["label"]), "label": r["label"],
                    "room": r.get("room"), "score": r.get("score"), "observations": r.get("observations"),
                    "n_frames": r.get("n_frames"), "first_frame": r.get("first_frame"),
                    "last_frame": r.get("last_frame"),
                    "last_seen": _when(seen) if seen is not None else None})
    return out


def _when(epoch) -> str:
    import datetime

    return datetime.datetime.fromtimestamp(float(epoch), datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")


def _expand_groups(store, q: Query) -> None:
    """Hierarchical counting: a group's labels come from a graph search of the stored taxonomy
    (IS_A*), which agrees with the offline file by construction (same source, version-marked)."""
    from sg3d.queries.taxonomy import Taxonomy, descendants

    leaves = Taxonomy.load().leaves
    for t in (q.target, q.anchor):
        if t is not None and t.how == "group":
            labels: set[str] = set()
            for name in t.names:
                labels |= descendants(store, name) & leaves
            t.labels = sorted(labels)


def _same_as_excess(run: _Run, q: Query, rooms) -> dict[str, int]:
    """Per label, how many matching objects are extra views of one physical object: each
    connected SAME_AS group of matching objects counts once (its members but one are extra,
    each charged to its own label)."""
    if not run.read("vqa_same_as_count")[0]["n"]:
        return {}
    pairs = run.read("vqa_same_as", **_filters(q, rooms))
    label = {p[end]: p[f"{end}_label"] for p in pairs for end in ("a", "b")}
    excess: dict[str, int] = {}
    for x, root in same_as_roots(pairs).items():
        if root != x:          # every member but the group's root is an extra view
            excess[label[x]] = excess.get(label[x], 0) + 1
    return excess
