"""The compiler of logical forms (queries/logic.py): templates read the scope, sets are computed.

A form whose every part is one of the simple forms (one kind of object, at most one stored
relation to another kind, a room) is answered by the per-form templates of queries/vqa.py, which
have index-chosen variants for large stores. Every other form is compiled here into two reads,
`vqa_scene_objects` (the objects of the scope, or of the labels the question names) and
`vqa_scene_relations` (their edges of the whitelisted types the form uses), and its sets are
evaluated over those rows: relation filters, negation (the complement within the set), distance
bands (box centre to box centre), extremes, name look-ups, counts and comparisons. One round trip
each; no subqueries (their results on the embedded store are wrong).

Rules the answers follow (each said in the answer where it matters):
- "objects"/"things" mean every object of the object layer, unnamed ones too; structure (floor,
  walls, counters, shelves, surfaces) is asked for by name.
- A colour word matches an object's main colour, as the per-room tallies count it; objects that
  have it only as their second colour (a white cup with red) are not counted, and the answer
  says how many there are.
- "how tall" is the box height along up; "how high" is the box top above the floor's top.
- No object of an asked class in scope: "I have not found ...", never "there is no ...".
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Optional

from ingest.model import COLOUR_NAMES, SHAPE_WORDS, UNNAMED_LABEL
from ingest.relation_rules import SYMMETRIC
from queries.grammar import DISTANCE_SUPERLATIVES, RELATIONS, SUPERLATIVES
from queries.lexicon import lemma, resolve
from queries.logic import NP, Filter, Form, fmt_m

STRUCTURE_LABELS = {"floor": "floor", "ground": "floor", "wall": "wall", "counter": "counter",
                    "countertop": "counter", "worktop": "counter", "shelf": "shelf", "surface": "surface"}
GENERIC = {"object", "thing", "item", "stuff", "everything", "something", "anything"}
COLOURS = {c: c for c in COLOUR_NAMES} | {"gray": "grey", "silver": "grey", "golden": "yellow"}
SIZES = {"big": "big", "large": "big", "huge": "big", "small": "small", "little": "small", "tiny": "small"}
# What a person may do -> the kinds of object that afford it (a small curated table).
AFFORDANCES: dict[str, tuple[list[str], list[str]]] = {   # verb -> (labels, structure labels)
    "sit": (["chair", "couch", "bench"], []),
    "sit down": (["chair", "couch", "bench"], []),
    "lie down": (["bed", "couch"], []), "sleep": (["bed", "couch"], []),
    "put": (["dining table"], ["counter", "shelf", "surface"]),
    "place": (["dining table"], ["counter", "shelf", "surface"]),
    "eat": (["dining table"], []), "wash": (["sink"], []), "watch": (["tv"], []),
    "read": (["book"], []), "drink": (["cup", "wine glass", "bottle"], []),
    "cook": (["oven", "microwave"], []), "work": (["laptop", "dining table"], []),
}
# "in the house": the whole store (or --building), not a room or an object
EVERYWHERE = {"house", "home", "building", "environment", "scene", "world", "map", "whole house",
              "whole building", "whole home", "total", "everywhere"}
STORED_TYPES = ("ON", "IN", "UNDER", "ABOVE", "BELOW", "NEXT_TO", "NEAR")
IMPLIED_BY = {"NEAR": ("NEAR", "NEXT_TO")}
ABSENT = "small or uncommon things may be missed"
LIST_SHOWN = 12
ROW_LIMIT = 100_000


class NotMine(Exception):
    """The form is one of the simple ones: queries/vqa.py answers it with its own templates."""


class Unanswerable(ValueError):
    """The form is read but cannot be answered (a word that names nothing); the text says why."""


@dataclass
class Resolved:
    """A noun phrase resolved against the store's vocabulary."""

    np: NP
    kind: str                            # named | any | structure | unknown | room
    labels: Optional[list[str]] = None   # None: any label of the kind
    names: list[str] = field(default_factory=list)
    colour: Optional[str] = None
    size: Optional[str] = None
    shape: Optional[str] = None
    room: Optional[str] = None
    room_ids: list[str] = field(default_factory=list)
    how: str = "label"
    notes: list[str] = field(default_factory=list)

    def noun(self, n: int = 2) -> str:
        from queries.vqa import plural

        if self.kind == "any":
            base = ("thing" if n == 1 else "things") if "thing" in self.np.text() else ("object" if n == 1 else "objects")
        elif len(self.names) == 1:
            base = plural(self.names[0], n)
        else:
            base = " or ".join(plural(x, n) for x in self.names)
        return " ".join(x for x in (self.size, self.shape, self.colour, base) if x)


def split_modifiers(words: list[str]) -> tuple[list[str], dict]:
    """Colour, size and shape words off a noun phrase (the first of each)."""
    mods: dict = {}
    rest = []
    for w in words:
        if w in COLOURS and "colour" not in mods:
            mods["colour"] = COLOURS[w]
        elif w in SIZES and "size" not in mods:
            mods["size"] = SIZES[w]
        elif w in SHAPE_WORDS and "shape" not in mods:
            mods["shape"] = w
        else:
            rest.append(w)
    return rest, mods


def resolve_np(np: NP, is_room: Callable[[str], list], embedding=None, use_embedding=True,
               may_be_room: bool = False) -> Resolved:
    """A noun phrase -> what it names: a room (`is_room(name)`: its stored rows), structure,
    every object, stored labels, or an object word no stored category covers (kind unknown:
    searched, not found)."""
    text = " ".join(np.words)
    if may_be_room and np.number is None and text:
        for name in (text, f"{text} room"):
            rows = is_room(name)
            if rows:
                return Resolved(np, "room", room=rows[0]["name"], names=[rows[0]["name"]],
                                room_ids=[r["id"] for r in rows])
    words, mods = split_modifiers(np.words)
    phrase = " ".join(words)
    base = lemma(phrase) if phrase and " " not in phrase else phrase
    if not phrase or base in GENERIC or phrase in GENERIC or lemma(words[-1]) in GENERIC and len(words) == 1:
        return Resolved(np, "any", None, [], **mods)
    if lemma(words[-1]) in STRUCTURE_LABELS and len(words) == 1:
        label = STRUCTURE_LABELS[lemma(words[-1])]
        return Resolved(np, "structure", [label], [label], **mods)
    hit, why = resolve(phrase, embedding, use_embedding)
    if hit is None:
        if not may_be_room and text and is_room(text):
            raise Unanswerable(f"'{text}' is a room; ask e.g. 'how many chairs are in the {text}'")
        raise Unanswerable(why)
    if hit.labels is None:
        return Resolved(np, "any", None, [], **mods)
    notes = []
    if hit.how == "embedding":
        notes.append(f"'{hit.phrase}' read as {' + '.join(hit.names)} (similarity {hit.similarity:.2f})")
    if hit.ignored:
        notes.append("ignored: " + " ".join(hit.ignored))
    kind = "unknown" if hit.how == "unknown" or not hit.labels else "named"
    return Resolved(np, kind, list(hit.labels), list(hit.names), how=hit.how, notes=notes, **mods)


# -- the scene: the scope's objects and edges, read once ---------------------------------------
class Scene:
    def __init__(self, run, rooms: Optional[list[str]], labels: Optional[list[str]] = None):
        from queries.vqa import _few_rooms

        self.run, self.rooms = run, rooms
        name = "vqa_scene_objects_in_rooms" if _few_rooms(rooms) else "vqa_scene_objects"
        rows = run.read(name, rooms=rooms, labels=labels, limit=ROW_LIMIT)
        self.objects = {r["id"]: r for r in rows}
        run.rows_by_id.update(self.objects)
        self._edges: Optional[list[dict]] = None
        self._floor: dict[str, Optional[float]] = {}
        self._up: Optional[dict] = None

    def edges(self) -> list[dict]:
        if self._edges is None:
            ids = sorted(self.objects)
            self._edges = self.run.read("vqa_scene_relations", ids=ids, types=list(STORED_TYPES)) if ids else []
        return self._edges

    def up(self, room: str):
        import numpy as np

        if self._up is None:
            rows = self.run.read("vqa_room_up", rooms=sorted({o["room"] for o in self.objects.values()}))
            self._up = {r["id"]: r.get("up") for r in rows}
        v = np.array(self._up.get(room) or (0.0, 0.0, 1.0), float)
        return v / (np.linalg.norm(v) or 1.0)

    def centre(self, o: dict):
        import numpy as np

        c = o.get("box_centre") or [o.get("x"), o.get("y"), o.get("z")]
        return np.array([float(v or 0.0) for v in c])

    def top(self, o: dict) -> float:
        """The box top along the room's up."""
        import numpy as np

        return float(np.dot(self.centre(o), self.up(o["room"]))) + float((o.get("size") or [0, 0, 0])[2]) / 2

    def floor_level(self, room: str) -> Optional[float]:
        """The top of the room's floor node along up; None when the room has no floor node."""
        if room not in self._floor:
            floors = [o for o in self.objects.values() if o["room"] == room and o["label"] == "floor"
                      and is_structure(o)]
            self._floor[room] = max(self.top(o) for o in floors) if floors else None
        return self._floor[room]

    def distance(self, a: dict, b: dict) -> float:
        import numpy as np

        return float(np.linalg.norm(self.centre(a) - self.centre(b)))


def is_structure(o: dict) -> bool:
    return (o.get("layer") or "object") == "structure"


def colour_match(o: dict, colour: Optional[str]) -> Optional[str]:
    """A colour word matches an object's main colour ('colour'); its second colour only
    'colour2' (not counted, but reported: "a white cup with red" is not a red cup); None."""
    if colour is None or o.get("colour") == colour:
        return "colour"
    if o.get("colour2") == colour:
        return "colour2"
    return None


# -- evaluation ---------------------------------------------------------------------------------
class Evaluator:
    def __init__(self, run, is_room, embedding=None, use_embedding=True):
        self.run, self.is_room = run, is_room
        self.scene: Scene = None    # type: ignore[assignment]  # set by load() once the scope is known
        self.embedding, self.use_embedding = embedding, use_embedding
        self.notes: list[str] = []
        self.absent: list[Resolved] = []     # asked kinds with no object at all in scope
        self._resolved: dict[int, Resolved] = {}

    def load(self, rooms: Optional[list[str]]) -> None:
        self.scene = Scene(self.run, rooms)

    def resolved(self, np: NP, may_be_room: bool = False) -> Resolved:
        if id(np) not in self._resolved:
            r = resolve_np(np, self.is_room, self.embedding, self.use_embedding, may_be_room)
            self.notes += [n for n in r.notes if n not in self.notes]
            self._resolved[id(np)] = r
        return self._resolved[id(np)]

    def kind_members(self, r: Resolved) -> list[dict]:
        objs = self.scene.objects.values()
        if r.kind == "any":
            return [o for o in objs if not is_structure(o)]
        if r.kind == "structure":
            return [o for o in objs if is_structure(o) and o["label"] in r.labels]
        if r.kind == "unknown":
            return []
        return [o for o in objs if o["label"] in r.labels and not is_structure(o)]

    def members(self, np: NP) -> list[dict]:
        if np.alternatives:
            seen: dict[str, dict] = {}
            for a in np.alternatives:
                for o in self.members(a):
                    seen.setdefault(o["id"], o)
            return sorted(seen.values(), key=lambda o: o["id"])
        r = self.resolved(np)
        if r.kind == "room":
            raise Unanswerable(f"'{np.text()}' is a room, not an object")
        base = self.kind_members(r)
        second: list[dict] = []
        if not base and r.kind in ("named", "unknown", "structure"):
            if r not in self.absent:
                self.absent.append(r)
        out = []
        for o in base:
            which = colour_match(o, r.colour)
            if which is None or (r.shape and o.get("shape") != r.shape):
                continue
            if which == "colour2":
                second.append(o)
                continue
            out.append(o)
        if second:
            self.notes.append(f"by main colour; {len(second)} more {r.noun(len(second)).replace(r.colour + ' ', '')} "
                              f"{'has' if len(second) == 1 else 'have'} {r.colour} as a second colour")
        out = self._by_size(out, r.size)
        if np.number is not None:
            out = self._numbered(np, r, out)
        for f in np.filters:
            out = self.apply(f, out)
        if np.superlative:
            out = self.extreme(out, np)
        return out

    def _by_size(self, rows: list[dict], size: Optional[str]) -> list[dict]:
        if size is None:
            return rows
        from queries.vqa import _by_size

        return _by_size(self.run, rows, size)

    def _numbered(self, np: NP, r: Resolved, rows: list[dict]) -> list[dict]:
        """'chair 3', 'tv 1': the object printed under that name (a kind of one: number 1)."""
        named = self.run.names(self.kind_members(r))
        want = f"{' '.join(np.words)} {np.number}"
        hit = [o for o in rows if named.get(o["id"]) == want]
        if not hit and np.number == 1 and len(rows) == 1:
            hit = rows
        if not hit:
            known = sorted(named[o["id"]] for o in self.kind_members(r))
            raise Unanswerable(f"no object is named '{want}' here" + (f" (names: {', '.join(known)})" if known else ""))
        return hit

    def apply(self, f: Filter, rows: list[dict]) -> list[dict]:
        others = self.members(f.other)
        if not others and f.other.filters and not f.other.number:
            # "on the table next to the pink book": no table is next to it, so the second
            # relation is read as one more condition on the objects asked about
            bare = NP(f.other.words, superlative=f.other.superlative, toward=f.other.toward,
                      definite=f.other.definite)
            self._resolved[id(bare)] = self.resolved(f.other)
            if self.members(bare):
                note = f"read as: {f.relation} {bare.describe()} and " + ", ".join(x.describe() for x in f.other.filters)
                self.notes.append(note)
                out = self.apply(Filter(f.kind, bare, f.relation, f.low_m, f.high_m, f.negated), rows)
                for g in f.other.filters:
                    out = self.apply(g, out)
                return out
        other_ids = {o["id"] for o in others}
        if f.kind == "rel":
            rel_type, symmetric = RELATIONS[f.relation]
            types = IMPLIED_BY.get(rel_type, (rel_type,))
            linked: set[str] = set()
            for e in self.scene.edges():
                if e["type"] not in types:
                    continue
                if e["o"] in other_ids:
                    linked.add(e["s"])
                if (symmetric or e["type"] in SYMMETRIC) and e["s"] in other_ids:
                    linked.add(e["o"])
            keep = {o["id"] for o in rows if o["id"] in linked and o["id"] not in other_ids}
        else:
            lo, hi = f.low_m, f.high_m
            keep = set()
            for o in rows:
                ds = [self.scene.distance(o, b) for b in others if b["id"] != o["id"]]
                if not ds:
                    continue
                d = min(ds)
                if (lo is None or d > lo) and (hi is None or d <= hi):
                    keep.add(o["id"])
            note = "distances are measured between box centres"
            if note not in self.notes:
                self.notes.append(note)
        if f.negated:
            return [o for o in rows if o["id"] not in keep and o["id"] not in other_ids]
        return [o for o in rows if o["id"] in keep]

    def key(self, np: NP) -> Callable[[dict], float]:
        if np.superlative in DISTANCE_SUPERLATIVES:
            others = self.members(np.toward)
            if not others:
                return lambda o: math.nan
            return lambda o: min((self.scene.distance(o, b) for b in others if b["id"] != o["id"]), default=math.nan)
        key, _ = SUPERLATIVES[np.superlative]
        if key == "volume":
            return lambda o: float(o.get("volume") or 0.0)
        if key == "height":
            return lambda o: float((o.get("size") or [0, 0, 0])[2])
        return self.scene.top

    def extreme(self, rows: list[dict], np: NP) -> list[dict]:
        sign = DISTANCE_SUPERLATIVES.get(np.superlative) or SUPERLATIVES[np.superlative][1]
        k = self.key(np)
        scored = [(k(o), o) for o in rows]
        scored = [(v, o) for v, o in scored if not math.isnan(v)]
        if not scored:
            return []
        best = max(scored, key=lambda vo: (sign * vo[0], vo[1]["id"]))
        return [best[1]]


# -- answers ------------------------------------------------------------------------------------
def _join(items: list[str]) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


class Answerer:
    def __init__(self, ev: Evaluator, room_label: Optional[str]):
        self.ev, self.scene, self.run = ev, ev.scene, ev.run
        self.where = f" in the {room_label}" if room_label else ""
        self.thumbnail: Optional[bytes] = None

    def names(self, rows: list[dict]) -> dict[str, str]:
        return self.run.names(rows)

    def listing(self, rows: list[dict]) -> str:
        from queries.naming import describe_unnamed
        from queries.vqa import the

        named = self.names(rows[:LIST_SHOWN])
        parts = []
        for o in sorted(rows[:LIST_SHOWN], key=lambda o: named[o["id"]]):
            name = the(named[o["id"]])
            if o["label"] == UNNAMED_LABEL:
                dims = describe_unnamed(o, with_size=True)
                name = f"{the(named[o['id']])} (about {dims.split(' about ')[-1]})" if " about " in dims else name
            parts.append(name)
        more = [f"{len(rows) - LIST_SHOWN} more"] if len(rows) > LIST_SHOWN else []
        return _join(parts + more) if parts else ""

    def noun_of(self, np: NP, n: int) -> str:
        if np.alternatives:
            return " or ".join(self.noun_of(a, n) for a in np.alternatives)
        if np.number is not None:
            return np.text()
        if not np.words:
            return "thing" if n == 1 else "things"
        return self.ev.resolved(np).noun(n)

    def phrase(self, np: NP, n: int, filters: list[Filter] = ()) -> str:
        extra = [f.describe_plain() if hasattr(f, "describe_plain") else _filter_text(self, f) for f in
                 list(np.filters) + list(filters)]
        return " ".join([self.noun_of(np, n)] + extra)

    def absence(self) -> Optional[str]:
        if not self.ev.absent:
            return None
        r = self.ev.absent[0]
        what = " or ".join(r.names) if r.names else r.np.text()
        article = "an" if what[:1] in "aeiou" else "a"
        return f"I have not found {article} {what}{self.where} ({ABSENT})"


def _filter_text(a: Answerer, f: Filter) -> str:
    neg = "not " if f.negated else ""
    other = f"the {a.phrase(f.other, 1)}" if not f.other.number else a.phrase(f.other, 1)
    if f.kind == "rel":
        return f"{neg}{f.relation} {other}"
    if f.low_m is None:
        return f"{neg}within {fmt_m(f.high_m)} of {other}"
    if f.high_m is None:
        return f"{neg}farther than {fmt_m(f.low_m)} from {other}"
    return f"{neg}between {fmt_m(f.low_m)} and {fmt_m(f.high_m)} from {other}"


def _sizes(o: dict) -> str:
    s = o.get("size") or []
    return " x ".join(f"{float(v):.2f}" for v in s) + " m" if s else "unknown"


def _value(o: dict, name: str) -> dict:
    out = {k: o.get(k) for k in ("id", "label", "colour", "colour2", "layer", "shape", "volume", "size", "room")
           if o.get(k) is not None}
    out["name"] = name
    return out


def _head(form: Form) -> NP:
    return form.sets[0] if form.sets else NP([])


def _all_rows(ev: Evaluator, form: Form, np: NP) -> list[dict]:
    rows = ev.members(np)
    for f in form.filters:
        rows = ev.apply(f, rows)
    return rows


def op_count(a: Answerer, form: Form):
    from queries.vqa import plural

    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    n = len(rows)
    text = f"{n} {a.phrase(np, n, form.filters)}{a.where}"
    labels: dict[str, int] = {}
    for o in rows:
        labels[o["label"]] = labels.get(o["label"], 0) + 1
    if len(labels) > 1:
        text += " (" + ", ".join(f"{v} {plural(k, v)}" for k, v in sorted(labels.items(), key=lambda kv: (-kv[1], kv[0]))) + ")"
    if n == 0 and a.absence():
        text = f"0: {a.absence()}"
    return text, n, rows


def op_exists(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    n = len(rows)
    if n:
        named = a.names(rows[:LIST_SHOWN])
        text = f"yes, {n} {a.phrase(np, n, form.filters)}{a.where}: " + _join(sorted(named[o['id']] for o in rows[:LIST_SHOWN]))
    else:
        text = a.absence() or f"no: I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"
    return text, n > 0, rows


def op_at_least(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    n, k = len(rows), form.number
    holds = n > k if form.compare == "more" else n < k
    return f"{'yes' if holds else 'no'}: {n} {a.phrase(np, n, form.filters)}{a.where}", holds, rows


def op_compare(a: Answerer, form: Form):
    x, y = form.sets[0], form.sets[1]
    rx, ry = _all_rows(a.ev, form, x), _all_rows(a.ev, form, y)
    holds = len(rx) > len(ry) if form.compare == "more" else len(rx) < len(ry)
    text = (f"{'yes' if holds else 'no'}: {len(rx)} {a.phrase(x, len(rx), form.filters)} and "
            f"{len(ry)} {a.phrase(y, len(ry), form.filters)}{a.where}")
    return text, holds, rx + ry


def op_list(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    n = len(rows)
    what = a.phrase(np, n, form.filters)
    if not rows:
        what = a.phrase(np, 1, form.filters) if np.words or np.alternatives else \
            "anything " + " ".join(_filter_text(a, f) for f in list(np.filters) + list(form.filters))
        return (a.absence() or f"nothing found: I have not found {what}{a.where} ({ABSENT})"), [], rows
    named = a.names(rows)
    return f"{n} {what}{a.where}: {a.listing(rows)}", [_value(o, named[o["id"]]) for o in rows], rows


def op_where(a: Answerer, form: Form):
    from queries import viewpoint as views
    from queries.vqa import the

    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    if not rows:
        return (a.absence() or f"I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"), [], rows
    shown = rows[:LIST_SHOWN]
    ids = {o["id"] for o in shown}
    places: dict[str, list[dict]] = {i: [] for i in ids}
    objs = a.scene.objects
    for e in a.scene.edges():
        if e["s"] in ids and e["o"] in objs:
            places[e["s"]].append({"rel": e["type"], "other_id": e["o"], "rel_score": e.get("score"),
                                   "other_label": objs[e["o"]]["label"], "other_colour": objs[e["o"]].get("colour")})
        if e["o"] in ids and e["type"] in SYMMETRIC and e["s"] in objs:
            places[e["o"]].append({"rel": e["type"], "other_id": e["s"], "rel_score": e.get("score"),
                                   "other_label": objs[e["s"]]["label"], "other_colour": objs[e["s"]].get("colour")})
    others = [objs[p["other_id"]] for ps in places.values() for p in ps]
    named = a.names(shown + others)
    parts = []
    for o in shown:
        said = views.describe_place(places[o["id"]], {k: the(v) for k, v in named.items()})
        room = (o.get("room") or "?").split("/", 1)[-1]
        parts.append(f"{the(named[o['id']])} is " + (f"{said}, in the {room}" if said else f"in the {room}"))
    more = f"; ... {len(rows) - len(shown)} more" if len(rows) > len(shown) else ""
    value = [{**_value(o, named[o["id"]]), "relations": [{"rel": p["rel"], "other_id": p["other_id"],
                                                          "other_label": p["other_label"]} for p in places[o["id"]]]}
             for o in shown]
    return "; ".join(parts) + more, value, rows


def op_attribute(a: Answerer, form: Form):
    from queries.vqa import the

    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    if not rows:
        return (a.absence() or f"I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"), None, rows
    named = a.names(rows[:LIST_SHOWN])
    values, parts = [], []
    for o in rows[:LIST_SHOWN]:
        v, said = _attribute_of(a, o, form.attribute)
        values.append(v)
        parts.append(f"{the(named[o['id']])} {said}")
    text = "; ".join(parts)
    if len(rows) > LIST_SHOWN:
        text += f"; ... {len(rows) - LIST_SHOWN} more"
    return text, values[0] if len(values) == 1 else values, rows


def _attribute_of(a: Answerer, o: dict, attribute: str):
    size = [float(v) for v in (o.get("size") or [0, 0, 0])]
    if attribute == "colour":
        c2 = f" with {o['colour2']}" if o.get("colour2") else ""
        return o.get("colour"), f"is {o.get('colour') or 'of unknown colour'}{c2}"
    if attribute == "size":
        return size, f"is {_sizes(o)} (w x d x h)"
    if attribute == "tall":
        return round(size[2], 3), f"is {size[2]:.2f} m tall (its box height)"
    if attribute in ("width", "length"):
        v = max(size[0], size[1]) if attribute == "length" else min(size[0], size[1])
        return round(v, 3), f"is {v:.2f} m {'long' if attribute == 'length' else 'wide'}"
    # high: the box top above the floor
    floor = a.scene.floor_level(o["room"])
    if floor is None:
        return None, (f"has a box {size[2]:.2f} m tall, but I have not found the floor of the "
                      f"{(o.get('room') or '').split('/', 1)[-1]}, so its height above it is unknown")
    h = a.scene.top(o) - floor
    return round(h, 3), f"reaches {h:.2f} m above the floor (top of its box)"


def op_extreme(a: Answerer, form: Form):
    from queries.vqa import the

    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    if not rows:
        return (a.absence() or f"I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"), None, rows
    o = rows[0]
    name = the(a.names([o])[o["id"]])
    k = a.ev.key(np)(o)
    if np.superlative in DISTANCE_SUPERLATIVES:
        detail = f"{k:.2f} m from the {a.phrase(np.toward, 1)}"
    else:
        key = SUPERLATIVES[np.superlative][0]
        detail = {"volume": f"{k:.3g} m^3", "height": f"{k:.2f} m tall", "top": f"top at {k:.2f} m"}[key]
    what = a.noun_of(np, 1)
    filters = " ".join(_filter_text(a, f) for f in np.filters)
    thumb = a.run.read("vqa_thumbnail", id=o["id"])
    a.thumbnail = thumb[0]["thumbnail"] if thumb else None
    return (f"the {np.superlative} {what}{' ' + filters if filters else ''}{a.where}: {name} ({detail})",
            _value(o, name), rows)


def op_distance(a: Answerer, form: Form):
    from queries.vqa import the

    x, y = form.sets[0], form.sets[1]
    rx, ry = a.ev.members(x), a.ev.members(y)
    if not rx or not ry:
        return (a.absence() or "I have not found both objects" + a.where + f" ({ABSENT})"), None, rx + ry
    pairs = [(a.scene.distance(p, q), p, q) for p in rx for q in ry if p["id"] != q["id"]]
    if not pairs:
        return "these name the same object", 0.0, rx
    d, p, q = min(pairs, key=lambda t: (t[0], t[1]["id"], t[2]["id"]))
    named = a.names([p, q])
    text = f"{the(named[p['id']])} is {d:.2f} m from {the(named[q['id']])} (box centre to box centre)"
    if len(pairs) > 1:
        text += f"; the closest of {len(pairs)} pairs"
    return text, round(d, 3), [p, q]


def op_rooms(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    per: dict[str, int] = {}
    for o in rows:
        per[o["room"]] = per.get(o["room"], 0) + 1
    if not per:
        return (a.absence() or f"none: no room holds {a.phrase(np, 1, form.filters)}"), [], rows
    text = ", ".join(f"{rid.split('/', 1)[-1]} ({k} {a.phrase(np, k)})" for rid, k in sorted(per.items()))
    return text, [{"room": r, "n": k} for r, k in sorted(per.items())], rows


def op_room_most(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    rooms = {r["id"]: r for r in a.run.read("vqa_rooms_all", building=None)}
    if a.scene.rooms is not None:
        rooms = {k: v for k, v in rooms.items() if k in a.scene.rooms}
    per = {rid: 0 for rid in rooms}
    for o in rows:
        per[o["room"]] = per.get(o["room"], 0) + 1
    if not per:
        return "the store holds no rooms", None, rows
    sign = 1 if form.compare == "more" else -1
    best = max(per.items(), key=lambda kv: (sign * kv[1], kv[0]))
    ties = [r for r, k in per.items() if k == best[1]]
    name = best[0].split("/", 1)[-1]
    text = f"the {name} ({best[1]} {a.phrase(np, best[1])})"
    if len(ties) > 1:
        text = "a tie: " + ", ".join(f"the {r.split('/', 1)[-1]}" for r in sorted(ties)) + f" ({best[1]} {a.phrase(np, best[1])} each)"
    if len(per) == 1:
        text += "; it is the only room in scope"
    return text, {"room": best[0], "n": best[1]}, rows


def op_rooms_next_to(a: Answerer, form: Form):
    r = a.ev.resolved(_head(form), may_be_room=True)
    if r.kind != "room":
        raise Unanswerable(f"'{_head(form).text()}' is not a room in the store")
    ids = r.room_ids
    rows = a.run.read("vqa_rooms_adjacent", rooms=ids)
    names = sorted({x["name"] for x in rows})
    if not names:
        return f"none: no room shares objects with the {r.room} (rooms are linked when a scan sees into both)", [], []
    return f"{_join(names)} (rooms that share objects with the {r.room})", names, []


def op_room_count(a: Answerer, form: Form):
    rows = a.run.read("vqa_rooms_all", building=None)
    names = sorted({r["name"] for r in rows})
    return f"{len(rows)} room{'s' if len(rows) != 1 else ''}: " + _join(names) if rows else "0 rooms", len(rows), []


def op_affordance(a: Answerer, form: Form):
    verb = form.verb or ""
    words = verb.split()
    key = next((k for k in sorted(AFFORDANCES, key=len, reverse=True) if words[:len(k.split())] == k.split()), None)
    if key is None:
        raise Unanswerable(f"I don't know what things afford '{verb}'")
    labels, structure = AFFORDANCES[key]
    objs = [o for o in a.scene.objects.values()
            if (o["label"] in labels and not is_structure(o)) or (o["label"] in structure and is_structure(o))]
    if not objs:
        return (f"I have not found anything to {key} on or at{a.where} (looked for "
                f"{_join(labels + structure)}; {ABSENT})"), [], []
    text = f"to {key}: {a.listing(objs)}{a.where} (things one can {key} on or at: {', '.join(labels + structure)})"
    return text, [o["id"] for o in objs], objs


OPS = {"count": op_count, "exists": op_exists, "at_least": op_at_least, "compare": op_compare,
       "list": op_list, "where": op_where, "attribute": op_attribute, "extreme": op_extreme,
       "distance": op_distance, "rooms": op_rooms, "room_most": op_room_most,
       "rooms_next_to": op_rooms_next_to, "room_count": op_room_count, "affordance": op_affordance}


# -- from question text to answer -----------------------------------------------------------------
SIMPLE_OPS = ("count", "exists", "list", "where", "attribute", "rooms")
# words the per-form reader (queries/parse.py) would pass over: a question holding one that the
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
    extreme or negation: the per-form templates of queries/vqa.py answer it."""
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


def typo_vocabulary() -> frozenset:
    """Every word a question may use: the grammar's, the object nouns (singular and plural),
    colours, sizes, shapes, structure, affordance verbs and common question words."""
    return _vocabulary()


@__import__("functools").cache
def _vocabulary() -> frozenset:
    import json

    from queries.grammar import RESERVED
    from queries.lexicon import SYNONYMS, vocabulary
    from queries.parse import FILLER
    from queries.taxonomy import Taxonomy
    from queries.vqa import plural

    words: set[str] = set(RESERVED) | set(FILLER) | set(COLOURS) | set(SIZES) | set(SHAPE_WORDS)
    words |= set(STRUCTURE_LABELS) | GENERIC | {w for x in EVERYWHERE for w in x.split()} | {w for k in AFFORDANCES for w in k.split()}
    words |= {"please", "tell", "know", "could", "would", "should", "me", "us", "find", "put", "my",
              "cup", "does", "kitchen", "bedroom", "bathroom", "office", "living", "dining", "objects",
              "things", "items", "walls", "shelves", "surfaces", "counters", "color", "colors", "whats",
              "everything", "total", "type", "types", "kind", "kinds", "piece", "pieces", "sort",
              "sorts", "ones", "visible", "present", "stored", "there", "up", "down", "yes", "no",
              "left", "right", "front", "behind", "seen", "as", "bigger", "smaller", "larger",
              "size", "sizes", "hello", "thanks", "thank", "get", "where", "on", "top", "something"}
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
    from queries.grammar import GrammarError, read

    try:
        return read(text), room_rows
    except GrammarError as first:
        if " room" not in f" {text}":
            raise
        names = sorted((n.lower() for n in all_room_names()), key=len, reverse=True)
        placeholders: dict[str, str] = {}
        out = f" {text} "
        for i, name in enumerate(names):
            if f" {name} " in out:
                token = "roomname" + "abcdefghijklmnopqrstuvwxyz"[i % 26] * (1 + i // 26)
                placeholders[token] = name
                out = out.replace(f" {name} ", f" {token} ")
        if not placeholders:
            raise first
        try:
            form = read(out.strip())
        except GrammarError:
            raise first from None

        def rows(name: str) -> list:
            return room_rows(placeholders.get(name.split()[-1], name)) if name.split() and \
                name.split()[-1] in placeholders else room_rows(name)
        return form, rows


def compile_question(run, text: str, room: Optional[str], building: Optional[str], room_rows, all_room_names,
                     scope: Callable, embedding=None, use_embedding=True) -> Outcome:
    """Read `text` (normalised, typos fixed) and answer it, or say that the per-form reader
    should (a simple form), or refuse naming the word not read."""
    from queries.grammar import GrammarError

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
    ev = Evaluator(run, rows_of, embedding, use_embedding)
    try:
        found = room_filters(form, ev)
        q_room = found[0].room if found else None
        if q_room and room and q_room.lower() != room.lower():
            return Outcome("refuse", f"the question says '{q_room}' but --room is '{room}'", form=logical)
        # the per-form reader knows plain ASCII room names only ("küche", "my room" are ours)
        plain_room = q_room is None or (q_room.isascii() and q_room.split()[0] not in ("my", "our", "this"))
        if plain_room and is_simple(form, ev):
            return Outcome("simple", text, form=logical, room=q_room)
        ev.load(scope(q_room or room))
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
