"""Sets of objects: noun phrases resolved to stored kinds, and evaluated over the scope's rows.

`Scene` reads the scope once (cypher/vqa_scene_objects*, cypher/vqa_scene_relations); the
`Evaluator` computes each noun phrase's members from those rows: kind, colour, size, shape,
"chair 3" names, relation filters, negation (the complement within the set), distance bands
(box centre to box centre) and extremes.

Rules: "objects"/"things" mean every object of the object layer, unnamed ones too; structure
(floor, walls, counters, shelves, surfaces) is asked for by name. A colour word matches an
object's main colour (as the per-room tallies count it); objects with it only as their second
colour are left out and counted in a note.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Optional

from sg3d.core.errors import Sg3dError
from sg3d.core.model import SHAPE_WORDS
from sg3d.core.relation_rules import SYMMETRIC, VIEWPOINT
from sg3d.core.stored import Row
from sg3d.queries.lexicon import Target, lemma, resolve
from sg3d.queries.logic import NP, Filter
from sg3d.queries.scoping import by_size, few_rooms
from sg3d.queries.vocabulary import (
    ACTIVITIES,
    AFFORDANCE_PARTICLES,
    AFFORDANCE_VERBS,
    COLOURS,
    DISTANCE_SUPERLATIVES,
    GENERIC,
    IMPLIED_BY,
    INVERSE,
    RELATIONS,
    ROW_LIMIT,
    SIZES,
    STORED_TYPES,
    STRUCTURE_LABELS,
    SUPERLATIVES,
)
from sg3d.queries.answer.wording import plural


class Unanswerable(Sg3dError, ValueError):
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
    target: Optional[Target] = None      # how the lexicon read the words (mapping, ignored words)

    def noun(self, n: int = 2) -> str:
        if self.kind == "any":
            base = ("thing" if n == 1 else "things") if "thing" in self.np.text() else ("object" if n == 1 else "objects")
        elif len(self.names) == 1:
            base = plural(self.names[0], n)
        else:
            base = " or ".join(plural(x, n) for x in self.names)
        return " ".join(x for x in (self.size, self.shape, self.colour, base) if x)


def activity(words: str) -> str:
    """The activity of the curated table (vocabulary.ACTIVITIES) that words ask for: "sitting",
    "take a seat", "pour water into", "put my cup down"; Unanswerable naming them otherwise."""
    said = words.split()

    def known(key: str) -> Optional[str]:
        return AFFORDANCE_VERBS.get(key) or AFFORDANCE_VERBS.get(lemma(key))

    if known(words):
        return known(words) or ""
    for n in range(len(said) - 1, 0, -1):
        head = said[:n]
        if not known(" ".join(head)):
            continue
        # the words after the verb: those saying how or where ("down", "cold") go with it, the
        # others name what is handled ("my cup", "food"); "keep food cold" is never "keep"
        how = [w for w in said[n:] if w in AFFORDANCE_PARTICLES]
        for key in (" ".join(head + how), " ".join(said[:1] + how)):
            if known(key):
                return known(key) or ""
        if not how:
            return known(" ".join(head)) or ""
        raise Unanswerable(f"I could not read '{how[-1]}' in '{words}' (things afford: {', '.join(ACTIVITIES)})")
    raise Unanswerable(f"I do not know what things afford '{words}' (I know: {', '.join(ACTIVITIES)})")


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
        return Resolved(np, "any", None, [], target=hit, **mods)
    notes = []
    if hit.how == "embedding":
        notes.append(f"'{hit.phrase}' read as {' + '.join(hit.names)} (similarity {hit.similarity:.2f})")
    if hit.ignored:
        notes.append("ignored: " + " ".join(hit.ignored))
    kind = "unknown" if hit.how == "unknown" or not hit.labels else "named"
    return Resolved(np, kind, list(hit.labels), list(hit.names), how=hit.how, notes=notes, target=hit, **mods)


# -- the scene: the scope's objects and edges, read once ---------------------------------------
class Scene:
    def __init__(self, run, rooms: Optional[list[str]], labels: Optional[list[str]] = None, anchored: bool = False,
                 colour: Optional[str] = None):
        """The scope's objects of `labels` (None: every one); `anchored` (a few rooms, `labels`
        the kinds the question names): also every object linked to one of them by a stored
        relation, with those edges, read from the anchors outwards (`_link`); `colour`: also every
        object whose main or second colour it is; past a few rooms every object of the scope is
        read instead of either."""
        self.run, self.rooms = run, rooms
        if (anchored or colour) and not few_rooms(rooms):
            anchored, colour, labels = False, None, None
        name = "vqa_scene_objects_in_rooms" if few_rooms(rooms) else "vqa_scene_objects"
        rows = run.read(name, rooms=rooms, labels=labels, limit=ROW_LIMIT)
        self.objects = {r["id"]: r for r in rows}
        self._edges: Optional[list[Row]] = None
        self._touching: dict[frozenset, list[Row]] = {}
        if anchored and labels is not None:
            self._link(rows)
        elif colour is not None:
            for r in run.read("vqa_scene_objects_coloured", rooms=rooms, colour=colour, limit=ROW_LIMIT):
                self.objects.setdefault(r["id"], r)
            self.objects = dict(sorted(self.objects.items()))
        run.rows_by_id.update(self.objects)
        self._floor: dict[str, Optional[float]] = {}
        self._up: Optional[dict] = None

    def _link(self, anchors: list[Row]) -> None:
        """Rule "read from the anchor outwards": the objects linked to the anchors by a stored
        relation and those edges (cypher/vqa_scene_linked: by the anchors' ids); the scene's edges
        are then every stored edge with an anchor at one end, in the order the whole scope's read
        gives (s, type, o), which is all a relation filter to the anchors reads."""
        edges: dict[tuple, dict] = {}
        if anchors:
            for r in self.run.read("vqa_scene_linked", ids=[a["id"] for a in anchors], types=list(STORED_TYPES),
                                   rooms=self.rooms):
                s, o = (r["anchor"], r["id"]) if r["outgoing"] else (r["id"], r["anchor"])
                edges[(s, r["type"], o)] = {"s": s, "type": r["type"], "o": o, "score": r["edge_score"]}
                self.objects.setdefault(r["id"], {k: v for k, v in r.items()
                                                  if k not in ("anchor", "type", "outgoing", "edge_score")})
        self.objects = dict(sorted(self.objects.items()))
        self._edges = [edges[k] for k in sorted(edges)]

    def edges_touching(self, ids: set[str]) -> list[Row]:
        """The scene's stored edges with an end in `ids` (what a relation filter to those objects
        reads): from the scene's edges when they are read, else read by those ids
        (cypher/vqa_scene_edges_of; a few rooms only), without reading every object's edges."""
        if self._edges is not None or not few_rooms(self.rooms):
            return [e for e in self.edges() if e["s"] in ids or e["o"] in ids]
        key = frozenset(ids)
        if key not in self._touching:
            edges: dict[tuple, dict] = {}
            rows = self.run.read("vqa_scene_edges_of", ids=sorted(ids), types=list(STORED_TYPES),
                                 rooms=self.rooms) if ids else []
            for r in rows:
                s, o = (r["anchor"], r["id"]) if r["outgoing"] else (r["id"], r["anchor"])
                edges[(s, r["type"], o)] = {"s": s, "type": r["type"], "o": o, "score": r["score"]}
            self._touching[key] = [edges[k] for k in sorted(edges)]
        return self._touching[key]

    def edges(self) -> list[Row]:
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
    def __init__(self, run, is_room, embedding=None, use_embedding=True, building: Optional[str] = None):
        self.run, self.is_room = run, is_room
        self.building = building.lower() if building else None     # rooms questions stay in it
        self.scene: Scene = None    # type: ignore[assignment]  # set by load() once the scope is known
        self.embedding, self.use_embedding = embedding, use_embedding
        self.notes: list[str] = []
        self.absent: list[Resolved] = []     # asked kinds with no object at all in scope
        self._resolved: dict[int, Resolved] = {}

    def load(self, rooms: Optional[list[str]], labels: Optional[list[str]] = None, anchored: bool = False,
             colour: Optional[str] = None) -> None:
        self.scene = Scene(self.run, rooms, labels, anchored, colour)

    def resolved(self, np: NP, may_be_room: bool = False) -> Resolved:
        if id(np) not in self._resolved:
            r = resolve_np(np, self.is_room, self.embedding, self.use_embedding, may_be_room)
            said = r.notes + ([f"ignored: {' '.join(np.ignored)}"] if np.ignored else [])
            self.notes += [n for n in said if n not in self.notes]
            self._resolved[id(np)] = r
        return self._resolved[id(np)]

    def kind_members(self, r: Resolved) -> list[Row]:
        objs = self.scene.objects.values()
        if r.kind == "any":
            return [o for o in objs if not is_structure(o)]
        if r.kind == "structure":
            return [o for o in objs if is_structure(o) and o["label"] in (r.labels or [])]
        if r.kind == "unknown":
            return []
        return [o for o in objs if o["label"] in (r.labels or []) and not is_structure(o)]

    def members(self, np: NP) -> list[Row]:
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
        second: list[Row] = []
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
            self.notes.append(f"by main colour; {len(second)} more {r.noun(len(second)).replace(f'{r.colour} ', '')} "
                              f"{'has' if len(second) == 1 else 'have'} {r.colour} as a second colour")
        out = self._by_size(out, r.size)
        if np.purpose:
            out = [o for o in out if o["label"] in ACTIVITIES[activity(np.purpose)]]
        if np.number is not None:
            out = self._numbered(np, r, out)
        for f in np.filters:
            out = self.apply(f, out)
        if np.superlative:
            out = self.extreme(out, np)
        return self._printed_name(np, out)

    def _printed_name(self, np: NP, rows: list[Row]) -> list[Row]:
        """"the white object on the dining table": when a singular phrase, with its relation
        words, is the printed name of exactly one of the rows, it means that object (the brown
        cup on the table is also a brown object on the table, but not the one so named)."""
        if len(rows) < 2 or np.indefinite or np.number is not None or not np.words or lemma(np.words[-1]) != np.words[-1]:
            return rows
        said = " ".join([np.text()] + [f"{f.relation} the {f.other.text()}" for f in np.filters
                                       if f.kind == "rel" and not f.negated and not f.other.alternatives])
        named = self.run.names(rows)
        exact = [o for o in rows if named.get(o["id"]) == said]
        return exact if len(exact) == 1 else rows

    def _by_size(self, rows: list[Row], size: Optional[str]) -> list[Row]:
        if size is None:
            return rows

        return by_size(self.run, rows, size)

    def _numbered(self, np: NP, r: Resolved, rows: list[Row]) -> list[Row]:
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

    def apply(self, f: Filter, rows: list[Row]) -> list[Row]:
        if f.kind == "except":      # "anything on the counter besides the sink"
            drop = {o["id"] for o in self.members(f.other)}
            return [o for o in rows if o["id"] not in drop]
        if f.kind == "rel" and RELATIONS[f.relation or ""][0] in VIEWPOINT:
            raise Unanswerable(f"'{f.relation}' depends on a viewpoint and is read in questions about one kind of "
                               f"object and one relation only (e.g. 'how many chairs are {f.relation} the table')")
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
                out = self.apply(Filter(f.kind, bare, f.relation, f.low_m, f.high_m, f.negated, f.reverse), rows)
                for g in f.other.filters:
                    out = self.apply(g, out)
                return out
        other_ids = {o["id"] for o in others}
        if f.kind == "rel":
            rel_type, symmetric = RELATIONS[f.relation or ""]
            types = IMPLIED_BY.get(rel_type, (rel_type,))
            linked: set[str] = set()
            inverse = INVERSE.get(rel_type, ())
            for e in self.scene.edges_touching(other_ids):
                if f.reverse:       # "what is the cup on": where the cup's own edge ends
                    if e["type"] in types and e["s"] in other_ids:
                        linked.add(e["o"])
                    if e["type"] in inverse and e["o"] in other_ids:
                        linked.add(e["s"])
                    if (symmetric or e["type"] in SYMMETRIC) and e["type"] in types and e["o"] in other_ids:
                        linked.add(e["s"])
                    continue
                if e["type"] in inverse and e["s"] in other_ids:    # desk -UNDER-> chair: chair above desk
                    linked.add(e["o"])
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
            others = self.members(np.toward) if np.toward is not None else []
            if not others:
                return lambda o: math.nan
            return lambda o: min((self.scene.distance(o, b) for b in others if b["id"] != o["id"]), default=math.nan)
        key, _ = SUPERLATIVES[np.superlative or ""]
        if key == "volume":
            return lambda o: float(o.get("volume") or 0.0)
        if key == "height":
            return lambda o: float((o.get("size") or [0, 0, 0])[2])
        return self.scene.top

    def extreme(self, rows: list[Row], np: NP) -> list[Row]:
        word = np.superlative or ""
        sign = DISTANCE_SUPERLATIVES.get(word) or SUPERLATIVES[word][1]
        k = self.key(np)
        scored = [(k(o), o) for o in rows]
        scored = [(v, o) for v, o in scored if not math.isnan(v)]
        if not scored:
            return []
        best = max(scored, key=lambda vo: (sign * vo[0], vo[1]["id"]))
        return [best[1]]




def same_as_roots(pairs, keep=None) -> dict[str, str]:
    """Each object id of the SAME_AS `pairs` (rows with "a", "b"; only pairs whose both ends are
    in `keep`, when given) -> the smallest id of its connected group: one physical object seen
    from two rooms is one group, and every member but its root is a further view of it."""
    parent: dict[str, str] = {}

    def find(x: str) -> str:
        while parent.setdefault(x, x) != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for p in pairs:
        if keep is not None and not (p["a"] in keep and p["b"] in keep):
            continue
        ra, rb = find(p["a"]), find(p["b"])
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    return {x: find(x) for x in list(parent)}
