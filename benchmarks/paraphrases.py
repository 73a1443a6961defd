"""Ordinary users' questions about three real rooms, each judged by an oracle over the stored graph.

    python -m benchmarks.paraphrases [--keep-home DIR | --home DIR] [--json] [--md FILE]

An independent benchmark of `sg3d ask`: the questions (benchmarks/paraphrases.md lists them,
grouped by form and room, with each one's oracle rule) were written by someone who never read
the question reader's code, grammar or tests, from a brief of the forms it should cover and from
what the three rooms hold. Nothing here is phrased the way the grammar expects.

Rooms (read from ../shared beside the checkout), built with default settings into one building
"default" of one store: kitchen (7-Scenes red kitchen), livingroom (the Open3D living-room
micro sequence), study (3DMatch study room, fragment-1 then fragment-2 into one room).
Without --home the rooms are built into a scratch home (removed afterwards, or kept in
--keep-home DIR); --home DIR reuses a home that already holds the three rooms.

Every question goes through `sg3d.app.ask.ask`, the call `sg3d ask`, `POST /ask` and the MCP
tool make, scoped to its room (`--room`), or to the whole building when it names its room in
words or asks about rooms. Its oracle is plain Python over the room's stored objects and edges
(templates object_all, relation_all, vqa_rooms_all; printed names from the store's naming),
computed afresh on every run: no expected answer is typed in. An answer is

- right: it holds the oracle's fact (the count, yes/no, the set of objects, the colour, a
  distance within 10 cm, a size within 5 cm, the room or rooms);
- wrong: it answers something else (a word silently ignored is wrong, not refused);
- refused: ok is false (the reader says it does not understand); the word it names is recorded.

Prints a table (right / wrong / refused per form and per room, each refusal with its word,
overall % right); --json prints one JSON object per question and a summary line instead;
--md FILE writes the question list with the oracle rules and the results.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Optional

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared"))
BUILDING = "default"
ROOMS: dict[str, tuple[Path, ...]] = {
    "kitchen": (SHARED / "data" / "7scenes-redkitchen",),
    "livingroom": (SHARED / "data" / "open3d-livingroom1-micro",),
    "study": (SHARED / "data" / "3dmatch-studyroom" / "fragment-1",
              SHARED / "data" / "3dmatch-studyroom" / "fragment-2"),
}
# How each room may be written in an answer.
ROOM_WORDS = {"kitchen": r"kitchen", "livingroom": r"living[ -]?room", "study": r"study(?:[ -]?room)?"}

PLACEMENT = ("ON", "IN", "UNDER", "ABOVE", "BELOW", "NEXT_TO", "NEAR")
COLOURS = ("red", "orange", "yellow", "green", "blue", "purple", "pink", "brown", "black", "white", "grey")

# What each affordance means to the oracle (COCO labels and sg3d's shape/structure labels).
# core: what an answer must name (all of it, or at least one, per question); allowed: what it may name.
SIT = ("chair", "couch", "bench", "bed", "toilet", "stool", "sofa")
DRINK = ("cup", "wine glass", "bottle", "mug", "glass")
SURFACES = ("dining table", "table", "desk", "counter", "cabinet", "shelf", "surface", "sideboard")
STORAGE = ("cabinet", "shelf", "refrigerator", "bookcase", "drawer", "cupboard", "wardrobe", "sideboard")
WORKPLACES = ("desk", "dining table", "table", "counter")


# ---------------------------------------------------------------------------------------------
# The graph as the store holds it


class Room:
    """One room's live objects (with printed names) and relation edges."""

    def __init__(self, name: str, objects: list[dict], edges: list[dict], names: dict[str, str]):
        self.name = name
        self.objects = objects
        self.edges = edges
        for o in objects:
            o["name"] = names.get(o["id"], o["label"])
        self.by_id = {o["id"]: o for o in objects}

    @classmethod
    def load(cls, store, name: str, building: str = BUILDING) -> "Room":
        from sg3d.core.model import RELATION_TYPES
        from sg3d.graphdb.values import room_id
        from sg3d.queries.naming import names_in_store    # the names answers print (not the reader)

        rid = room_id(building, name)
        objects = [dict(r["o"]) for r in store.read("object_all", room=rid) if r["o"].get("removed_at") is None]
        for o in objects:
            o.pop("hist", None)
            o.pop("thumbnail", None)
        edges = [dict(e) for e in store.read("relation_all", room=rid, types=list(RELATION_TYPES))]
        return cls(name, objects, edges, names_in_store(store.read, objects))

    def things(self) -> list[dict]:
        """The object layer: what "things" and "objects" mean (the structure layer left out)."""
        return [o for o in self.objects if (o.get("layer") or "object") != "structure"]

    def structure(self) -> list[dict]:
        return [o for o in self.objects if (o.get("layer") or "object") == "structure"]

    def edge_set(self) -> set[tuple[str, str, str]]:
        return {(e["s"], e["type"], e["o"]) for e in self.edges}


class World:
    """Every room of the building, and the rooms' list as the store has it."""

    def __init__(self, rooms: dict[str, Room], room_names: list[str]):
        self.rooms = rooms
        self.room_names = room_names

    @classmethod
    def load(cls, store, names: Iterable[str] = tuple(ROOMS), building: str = BUILDING) -> "World":
        listed = [r["name"] for r in store.read("vqa_rooms_all", building=building)]
        return cls({n: Room.load(store, n, building) for n in names if n in listed}, listed)

    def names(self) -> dict[str, str]:
        """{id: printed name} over every room."""
        return {o["id"]: o["name"] for r in self.rooms.values() for o in r.objects}


# ---------------------------------------------------------------------------------------------
# Sets of objects: small expressions that know how to describe themselves (the oracle rules)


@dataclass(frozen=True)
class S:
    fn: Callable[[Room], list[dict]]
    desc: str

    def __call__(self, room: Room) -> list[dict]:
        seen, out = set(), []
        for o in self.fn(room):
            if o["id"] not in seen:
                seen.add(o["id"])
                out.append(o)
        return out

    def __sub__(self, other: "S") -> "S":
        return S(lambda r: [o for o in self(r) if o["id"] not in {x["id"] for x in other(r)}],
                 f"{self.desc} except {other.desc}")

    def __or__(self, other: "S") -> "S":
        return S(lambda r: self(r) + other(r), f"{self.desc} or {other.desc}")


def L(*labels: str, colour: Optional[str] = None) -> S:
    """Object-layer nodes with one of these labels (and this colour)."""
    desc = " or ".join(f"label={x!r}" for x in labels) + (f" colour={colour!r}" if colour else "")
    return S(lambda r: [o for o in r.things() if o["label"] in labels and (colour is None or o.get("colour") == colour)],
             f"[{desc}]")


def STRUCT(*labels: str) -> S:
    return S(lambda r: [o for o in r.structure() if o["label"] in labels], "[structure " + "/".join(labels) + "]")


THINGS = S(lambda r: r.things(), "[every object-layer node]")


def COL(colour: str) -> S:
    return S(lambda r: [o for o in r.things() if o.get("colour") == colour], f"[object-layer colour={colour!r}]")


def NOT_LABEL(xs: S, *labels: str) -> S:
    return S(lambda r: [o for o in xs(r) if o["label"] not in labels], f"{xs.desc} whose label is not {'/'.join(labels)}")


def NOT_COLOUR(xs: S, colour: str) -> S:
    return S(lambda r: [o for o in xs(r) if o.get("colour") != colour], f"{xs.desc} whose colour is not {colour}")


# A relation word -> (edge type, direction) pairs: "fwd" = X -type-> Y, "back" = Y -type-> X.
RELATION_WORDS: dict[str, tuple[tuple[str, str], ...]] = {
    "on": (("ON", "fwd"),),
    "in": (("IN", "fwd"),),
    "next to": (("NEXT_TO", "fwd"), ("NEXT_TO", "back")),
    "near": (("NEAR", "fwd"), ("NEAR", "back"), ("NEXT_TO", "fwd"), ("NEXT_TO", "back")),
    # ordinary English: under/below = beneath, touching or not; above = over, not resting on
    "under": (("UNDER", "fwd"), ("BELOW", "fwd"), ("ABOVE", "back")),
    "above": (("ABOVE", "fwd"), ("BELOW", "back"), ("UNDER", "back")),
}
RELATION_DEFS = {
    "on": "X -ON-> Y", "in": "X -IN-> Y", "next to": "NEXT_TO either way",
    "near": "NEAR or NEXT_TO, either way", "under": "X -UNDER|BELOW-> Y or Y -ABOVE-> X",
    "above": "X -ABOVE-> Y or Y -BELOW|UNDER-> X",
}


def rel(xs: S, word: str, ys: S) -> S:
    """The X of `xs` that stand in relation `word` to some Y of `ys` (X != Y)."""
    def fn(r: Room) -> list[dict]:
        yids = {y["id"] for y in ys(r)}
        hit = set()
        for e in r.edges:
            for typ, way in RELATION_WORDS[word]:
                if e["type"] != typ:
                    continue
                x, y = (e["s"], e["o"]) if way == "fwd" else (e["o"], e["s"])
                if y in yids and x != y:
                    hit.add(x)
        return [o for o in xs(r) if o["id"] in hit]
    return S(fn, f"{xs.desc} {word} ({RELATION_DEFS[word]}) {ys.desc}")


def anchors(room: Room, subject: dict) -> set[str]:
    """Ids of everything the subject has a placement edge with, either way."""
    out = set()
    for e in room.edges:
        if e["type"] in PLACEMENT:
            if e["s"] == subject["id"]:
                out.add(e["o"])
            elif e["o"] == subject["id"]:
                out.add(e["s"])
    return out


def centre(o: dict) -> list[float]:
    return [float(v) for v in (o.get("box_centre") or [o["x"], o["y"], o["z"]])]


def dist(a: dict, b: dict) -> float:
    return math.dist(centre(a), centre(b))


# ---------------------------------------------------------------------------------------------
# Truths: what the oracle computes, and how an answer is judged against it


@dataclass
class Truth:
    kind: str                 # count | yesno | objects | colour | length | dims | where | where_all | afford | room | rooms | pick
    value: Any = None
    extra: dict[str, Any] = field(default_factory=dict)

    def show(self, names: dict[str, str]) -> str:
        if self.kind in ("objects", "afford", "where", "where_all", "pick"):
            ids = self.value if isinstance(self.value, (set, list)) else [self.value]
            label = sorted(names.get(str(i), str(i)) for i in ids)
            if self.kind == "afford":
                return f"{'all of' if self.extra['need'] == 'all' else 'one of'} {label or 'nothing'}"
            return str(label) if label else "nothing"
        if self.kind in ("length",):
            return f"{self.value:.2f} m" if self.value is not None else "none"
        if self.kind == "dims":
            return "x".join(f"{v:.2f}" for v in self.value) + " m" if self.value else "none"
        if self.kind == "rooms":
            return str(sorted(self.value))
        return str(self.value)


Oracle = Callable[["World", Room], Truth]


def count(xs: S) -> tuple[Oracle, str]:
    return (lambda w, r: Truth("count", len(xs(r)))), f"count of {xs.desc}"


def exists(xs: S, want: bool = True) -> tuple[Oracle, str]:
    return (lambda w, r: Truth("yesno", bool(xs(r)) == want)), ("yes iff any " if want else "yes iff none of ") + xs.desc


def none_of(xs: S) -> tuple[Oracle, str]:
    return exists(xs, want=False)


def quantity(xs: S, op: str, n: int) -> tuple[Oracle, str]:
    ops = {">=": lambda a: a >= n, ">": lambda a: a > n, "==": lambda a: a == n, "<": lambda a: a < n}
    return (lambda w, r: Truth("yesno", ops[op](len(xs(r))))), f"yes iff count of {xs.desc} {op} {n}"


def objects(xs: S) -> tuple[Oracle, str]:
    return (lambda w, r: Truth("objects", {o["id"] for o in xs(r)})), f"exactly the set {xs.desc}"


def colour_of(xs: S) -> tuple[Oracle, str]:
    def fn(w, r):
        cs = {o.get("colour") for o in xs(r)}
        return Truth("colour", cs.pop() if len(cs) == 1 else None)
    return fn, f"the colour of {xs.desc} (all of them, one colour)"


def measure(xs: S, dim: str) -> tuple[Oracle, str]:
    pick = {"height": lambda s: s[2], "width": lambda s: s[0], "length": lambda s: max(s[0], s[1])}[dim]
    def fn(w, r):
        os_ = xs(r)
        return Truth("length", float(pick(os_[0]["size"])) if len(os_) == 1 else None, {"tol": 0.05})
    return fn, f"{dim} of the one {xs.desc} (size = width, depth, height; length = max(width, depth)), within 5 cm"


def dims(xs: S) -> tuple[Oracle, str]:
    def fn(w, r):
        os_ = xs(r)
        return Truth("dims", [float(v) for v in os_[0]["size"]] if len(os_) == 1 else None)
    return fn, f"the three box dimensions of the one {xs.desc}, each within 5 cm (or its volume within 10 %)"


def distance(xs: S, ys: Optional[S] = None) -> tuple[Oracle, str]:
    """The distance between box centres: the one X and the one Y, the two X (ys None), or the
    closest X-Y pair when several."""
    def fn(w, r):
        a = xs(r)
        b = a if ys is None else ys(r)
        pairs = [dist(x, y) for x in a for y in b if x["id"] != y["id"]]
        return Truth("length", min(pairs) if pairs else None, {"tol": 0.10})
    what = f"the two of {xs.desc}" if ys is None else f"{xs.desc} and {ys.desc} (closest pair)"
    return fn, f"box-centre distance between {what}, within 10 cm"


def vol(o: dict) -> float:
    return float(o.get("volume") or 0.0)


def bigger(a: S, b: S, smaller: bool = False) -> tuple[Oracle, str]:
    def fn(w, r):
        va, vb = max(map(vol, a(r)), default=0.0), max(map(vol, b(r)), default=0.0)
        return Truth("yesno", va < vb if smaller else va > vb)
    return fn, f"yes iff volume of {a.desc} {'<' if smaller else '>'} volume of {b.desc}"


def pick_bigger(a: S, b: S) -> tuple[Oracle, str]:
    def fn(w, r):
        xa, xb = a(r), b(r)
        winner = max(xa + xb, key=vol)
        return Truth("pick", winner["id"], {"candidates": {o["id"] for o in xa + xb}})
    return fn, f"the larger by volume of {a.desc} and {b.desc}"


def where(xs: S) -> tuple[Oracle, str]:
    def fn(w, r):
        subj = xs(r)
        return Truth("where", {o["id"] for o in subj},
                     {"anchors": {o["id"]: anchors(r, o) for o in subj}, "room": r.name, "edges": r.edge_set()})
    return fn, (f"places the one {xs.desc} by at least one object, and every placement it states "
                f"holds in the graph, direction included (the room when it has no placement edge)")


def where_all(xs: S) -> tuple[Oracle, str]:
    def fn(w, r):
        subj = xs(r)
        return Truth("where_all", {o["id"] for o in subj},
                     {"anchors": {o["id"]: anchors(r, o) for o in subj}, "room": r.name, "edges": r.edge_set()})
    return fn, (f"a clause for every one of {xs.desc}, each placing it by at least one object, every "
                f"placement stated holding in the graph, direction included")


def afford(core: S, allowed: S, need: str) -> tuple[Oracle, str]:
    def fn(w, r):
        return Truth("afford", {o["id"] for o in core(r)}, {"allowed": {o["id"] for o in allowed(r)}, "need": need})
    return fn, (f"names {'every one' if need == 'all' else 'at least one'} of {core.desc} "
                f"(or says there is none when there is none) and nothing outside {allowed.desc}")


def room_count(xs: S) -> tuple[Oracle, str]:
    def fn(w, r):
        return Truth("count", sum(bool(xs(room)) for room in w.rooms.values()))
    return fn, f"number of rooms holding any {xs.desc}"


def rooms_with(xs: S) -> tuple[Oracle, str]:
    def fn(w, r):
        return Truth("rooms", {n for n, room in w.rooms.items() if xs(room)})
    return fn, f"the rooms holding any {xs.desc}"


def room_extreme(xs: S, most: bool = True, among: Optional[tuple[str, ...]] = None) -> tuple[Oracle, str]:
    def fn(w, r):
        counts = {n: len(xs(room)) for n, room in w.rooms.items() if among is None or n in among}
        best = (max if most else min)(counts.values())
        winners = {n for n, c in counts.items() if c == best}
        return Truth("room", winners.pop() if len(winners) == 1 else None)
    scope = f" among {', '.join(among)}" if among else ""
    return fn, f"the room with the {'most' if most else 'fewest'} {xs.desc}{scope}"


def rooms_fewest(xs: S, n: int) -> tuple[Oracle, str]:
    def fn(w, r):
        ranked = sorted(w.rooms, key=lambda name: (len(xs(w.rooms[name])), name))
        return Truth("rooms", set(ranked[:n]))
    return fn, f"the {n} rooms with the fewest {xs.desc}"


def total_count(xs: S) -> tuple[Oracle, str]:
    return (lambda w, r: Truth("count", sum(len(xs(room)) for room in w.rooms.values()))), f"count of {xs.desc} over every room"


def room_total() -> tuple[Oracle, str]:
    return (lambda w, r: Truth("count", len(w.room_names))), "number of rooms in the building"


# ---------------------------------------------------------------------------------------------
# The questions

@dataclass
class Q:
    room: str                 # whose graph the oracle reads ('building' = all rooms)
    form: str
    text: str
    oracle: Oracle
    rule: str
    scope: Optional[str]      # the --room the question is asked with (None: the whole building)


FORMS = {
    "count": "counting",
    "exists": "existence",
    "attribute": "attributes (colour, size)",
    "where": "where is",
    "relation": "relations (on, under, next to, near, in, above, below)",
    "distance": "distance",
    "size": "size comparison",
    "negation": "existential negation and quantity",
    "rooms": "rooms by content",
    "attr_set": "attribute-only sets",
    "article": "'a X' (any) and 'the X' (one)",
    "indirect": "imperative and indirect frames, possessives",
    "affordance": "affordances",
    "where_all": "positions of all objects of a kind",
}

TABLE = L("dining table")
TABLES = L("dining table", "table", "desk")
CHAIRS, CUPS, BOOKS, TVS = L("chair"), L("cup"), L("book"), L("tv")
SINK, CABINET, FRIDGE, DESKS = L("sink"), L("cabinet"), L("refrigerator"), L("desk")
FLOOR, SHELVES, COUNTER = STRUCT("floor"), STRUCT("shelf"), STRUCT("counter")
SITTABLE, DRINKABLE = L(*SIT), L(*DRINK)
STORE_PLACES = L(*STORAGE) | STRUCT("shelf")
PUT_PLACES = L(*SURFACES) | STRUCT("counter", "shelf", "surface")
WORK_PLACES = L(*WORKPLACES) | STRUCT("counter")


def _q(room: str, form: str, text: str, oracle_rule: tuple[Oracle, str], scope: Optional[str] = "same") -> Q:
    oracle, rule = oracle_rule
    return Q(room, form, text, oracle, rule, room if scope == "same" else scope)


def questions() -> list[Q]:
    K, LV, ST, B = "kitchen", "livingroom", "study", "building"
    qs = [
        # ---------------- kitchen
        _q(K, "count", "how many chairs are in here?", count(CHAIRS)),
        _q(K, "count", "how many cups do you see?", count(CUPS)),
        _q(K, "count", "how many TVs are there in this room?", count(TVS)),
        _q(K, "count", "how many white mugs are there?", count(L("cup", colour="white"))),
        _q(K, "count", "how many things are sitting on the table?", count(rel(THINGS, "on", TABLE))),
        _q(K, "count", "how many cups are on the table?", count(rel(CUPS, "on", TABLE))),
        _q(K, "count", "how many green chairs are there?", count(L("chair", colour="green"))),
        _q(K, "count", "what's the number of books here?", count(BOOKS)),
        _q(K, "count", "how many chairs are pulled up next to the table?", count(rel(CHAIRS, "next to", TABLE))),
        _q(K, "exists", "is there a fridge?", exists(FRIDGE)),
        _q(K, "exists", "do you see any books?", exists(BOOKS)),
        _q(K, "exists", "are there any red cups?", exists(L("cup", colour="red"))),
        _q(K, "exists", "is there a sink here?", exists(SINK)),
        _q(K, "exists", "any laptops around?", exists(L("laptop"))),
        _q(K, "exists", "have you spotted a microwave?", exists(L("microwave"))),
        _q(K, "attribute", "what colour is the dining table?", colour_of(TABLE)),
        _q(K, "attribute", "what color is the sink?", colour_of(SINK)),
        _q(K, "attribute", "which colour are the chairs?", colour_of(CHAIRS)),
        _q(K, "attribute", "how tall is the dining table?", measure(TABLE, "height")),
        _q(K, "attribute", "how long is the table?", measure(TABLE, "length")),
        _q(K, "attribute", "what size is the sink?", dims(SINK)),
        _q(K, "where", "where's the sink?", where(SINK)),
        _q(K, "where", "where is the purple book?", where(L("book", colour="purple"))),
        _q(K, "where", "where can I find the grey cup?", where(L("cup", colour="grey"))),
        _q(K, "where", "whereabouts is the dining table?", where(TABLE)),
        _q(K, "relation", "what's on the dining table?", objects(rel(THINGS, "on", TABLE))),
        _q(K, "relation", "what is next to the sink?", objects(rel(THINGS, "next to", SINK))),
        _q(K, "relation", "is the grey cup on the table?", exists(rel(L("cup", colour="grey"), "on", TABLE))),
        _q(K, "relation", "is the purple book lying on the table?", exists(rel(L("book", colour="purple"), "on", TABLE))),
        _q(K, "relation", "what is sitting on the floor?", objects(rel(THINGS, "on", FLOOR))),
        _q(K, "relation", "is there anything in the sink?", exists(rel(THINGS, "in", SINK))),
        _q(K, "relation", "what's near the purple book?", objects(rel(THINGS, "near", L("book", colour="purple")))),
        _q(K, "relation", "what is on top of the counter?", objects(rel(THINGS, "on", COUNTER))),
        _q(K, "relation", "what's on the shelves?", objects(rel(THINGS, "on", SHELVES))),
        _q(K, "relation", "is there anything under the table?", exists(rel(THINGS, "under", TABLE))),
        _q(K, "distance", "how far is the sink from the dining table?", distance(SINK, TABLE)),
        _q(K, "distance", "how far apart are the two tvs?", distance(TVS)),
        _q(K, "distance", "what's the distance between the two cups on the table?", distance(rel(CUPS, "on", TABLE))),
        _q(K, "distance", "how far is the purple book from the white book?",
           distance(L("book", colour="purple"), L("book", colour="white"))),
        _q(K, "distance", "how many metres is the grey cup from the sink?", distance(L("cup", colour="grey"), SINK)),
        _q(K, "size", "is the table bigger than the sink?", bigger(TABLE, SINK)),
        _q(K, "size", "which is bigger, the sink or the grey cup?", pick_bigger(SINK, L("cup", colour="grey"))),
        _q(K, "size", "is the purple book smaller than the white book?",
           bigger(L("book", colour="purple"), L("book", colour="white"), smaller=True)),
        _q(K, "size", "which is larger: the dining table or the sink?", pick_bigger(TABLE, SINK)),
        _q(K, "negation", "is there anything on the table besides the cups?", exists(NOT_LABEL(rel(THINGS, "on", TABLE), "cup"))),
        _q(K, "negation", "what's on the table other than the cups?", objects(NOT_LABEL(rel(THINGS, "on", TABLE), "cup"))),
        _q(K, "negation", "is there anything on the table that isn't a book?", exists(NOT_LABEL(rel(THINGS, "on", TABLE), "book"))),
        _q(K, "negation", "are there at least 4 chairs?", quantity(CHAIRS, ">=", 4)),
        _q(K, "negation", "are there more than 3 cups?", quantity(CUPS, ">", 3)),
        _q(K, "negation", "are there exactly two tvs?", quantity(TVS, "==", 2)),
        _q(K, "negation", "how many things on the table are not cups?", count(NOT_LABEL(rel(THINGS, "on", TABLE), "cup"))),
        _q(K, "attr_set", "what is red?", objects(COL("red"))),
        _q(K, "attr_set", "which things are black?", objects(COL("black"))),
        _q(K, "attr_set", "what's purple in here?", objects(COL("purple"))),
        _q(K, "attr_set", "list everything that is white", objects(COL("white"))),
        _q(K, "article", "is there a cup on the table?", exists(rel(CUPS, "on", TABLE))),
        _q(K, "article", "is a chair next to the table?", exists(rel(CHAIRS, "next to", TABLE))),
        _q(K, "article", "is the sink next to a chair?", exists(rel(SINK, "next to", CHAIRS))),
        _q(K, "article", "is there a book on the floor?", exists(rel(BOOKS, "on", FLOOR))),
        _q(K, "article", "is the white book on the table?", exists(rel(L("book", colour="white"), "on", TABLE))),
        _q(K, "indirect", "could you tell me how many chairs there are?", count(CHAIRS)),
        _q(K, "indirect", "I'd like to know what is on the table", objects(rel(THINGS, "on", TABLE))),
        _q(K, "indirect", "please tell me where the sink is", where(SINK)),
        _q(K, "indirect", "count the cups for me, please", count(CUPS)),
        _q(K, "indirect", "how many chairs the kitchen has", count(CHAIRS), scope=None),
        _q(K, "indirect", "the kitchen's cups, how many are there?", count(CUPS), scope=None),
        _q(K, "indirect", "I wonder whether there's a tv in the kitchen", exists(TVS), scope=None),
        _q(K, "indirect", "can you show me what's on the table, please?", objects(rel(THINGS, "on", TABLE))),
        _q(K, "affordance", "where can I sit down?", afford(SITTABLE, SITTABLE, "all")),
        _q(K, "affordance", "what could I drink from?", afford(DRINKABLE, DRINKABLE, "all")),
        _q(K, "affordance", "where can I put my plate down?", afford(TABLES | COUNTER, PUT_PLACES, "any")),
        _q(K, "affordance", "where could I store things?", afford(STORE_PLACES, STORE_PLACES | PUT_PLACES, "any")),
        _q(K, "affordance", "is there somewhere I can work?", afford(TABLES | COUNTER, WORK_PLACES, "any")),
        _q(K, "where_all", "where are all the chairs?", where_all(CHAIRS)),
        _q(K, "where_all", "where are the cups?", where_all(CUPS)),
        _q(K, "where_all", "where are the tvs?", where_all(TVS)),

        # ---------------- living room
        _q(LV, "count", "how many chairs are in the living room?", count(CHAIRS)),
        _q(LV, "count", "how many tvs are there?", count(TVS)),
        _q(LV, "count", "how many things are standing on the floor?", count(rel(THINGS, "on", FLOOR))),
        _q(LV, "count", "how many sofas are there?", count(L("couch"))),
        _q(LV, "count", "how many objects does this room hold?", count(THINGS)),
        _q(LV, "exists", "is there a sofa?", exists(L("couch"))),
        _q(LV, "exists", "is there a television?", exists(TVS)),
        _q(LV, "exists", "do you see a cabinet?", exists(CABINET)),
        _q(LV, "exists", "is there a potted plant?", exists(L("potted plant"))),
        _q(LV, "attribute", "what colour is the cabinet?", colour_of(CABINET)),
        _q(LV, "attribute", "what colour is the armchair?", colour_of(CHAIRS)),
        _q(LV, "attribute", "how wide is the cabinet?", measure(CABINET, "width")),
        _q(LV, "attribute", "how tall is the tv?", measure(TVS, "height")),
        _q(LV, "where", "where is the tv?", where(TVS)),
        _q(LV, "where", "where's the chair?", where(CHAIRS)),
        _q(LV, "where", "where is the cabinet?", where(CABINET)),
        _q(LV, "relation", "what is on the cabinet?", objects(rel(THINGS, "on", CABINET))),
        _q(LV, "relation", "what is above the cabinet?", objects(rel(THINGS, "above", CABINET))),
        _q(LV, "relation", "what's below the tv?", objects(rel(THINGS, "under", TVS))),
        _q(LV, "relation", "is the tv above the cabinet?", exists(rel(TVS, "above", CABINET))),
        _q(LV, "relation", "what is next to the chair?", objects(rel(THINGS, "next to", CHAIRS))),
        _q(LV, "relation", "what's near the tv?", objects(rel(THINGS, "near", TVS))),
        _q(LV, "relation", "is there anything inside the cabinet?", exists(rel(THINGS, "in", CABINET))),
        _q(LV, "relation", "is the tv on the floor?", exists(rel(TVS, "on", FLOOR))),
        _q(LV, "distance", "how far is the chair from the tv?", distance(CHAIRS, TVS)),
        _q(LV, "distance", "how far apart are the tv and the cabinet?", distance(TVS, CABINET)),
        _q(LV, "distance", "what's the distance from the chair to the cabinet?", distance(CHAIRS, CABINET)),
        _q(LV, "size", "is the cabinet bigger than the tv?", bigger(CABINET, TVS)),
        _q(LV, "size", "which is bigger, the chair or the tv?", pick_bigger(CHAIRS, TVS)),
        _q(LV, "size", "is the tv larger than the chair?", bigger(TVS, CHAIRS)),
        _q(LV, "negation", "is there anything on the floor besides the chair?", exists(NOT_LABEL(rel(THINGS, "on", FLOOR), "chair"))),
        _q(LV, "negation", "is there something on the cabinet that is not white?", exists(NOT_COLOUR(rel(THINGS, "on", CABINET), "white"))),
        _q(LV, "negation", "are there at least two chairs?", quantity(CHAIRS, ">=", 2)),
        _q(LV, "negation", "is there exactly one tv?", quantity(TVS, "==", 1)),
        _q(LV, "negation", "are there more than 5 things on the floor?", quantity(rel(THINGS, "on", FLOOR), ">", 5)),
        _q(LV, "attr_set", "what is white?", objects(COL("white"))),
        _q(LV, "attr_set", "which things are brown?", objects(COL("brown"))),
        _q(LV, "attr_set", "what's black in here?", objects(COL("black"))),
        _q(LV, "article", "is there a chair next to the cabinet?", exists(rel(CHAIRS, "next to", CABINET))),
        _q(LV, "article", "is the tv near a chair?", exists(rel(TVS, "near", CHAIRS))),
        _q(LV, "indirect", "could you tell me what's on the cabinet?", objects(rel(THINGS, "on", CABINET))),
        _q(LV, "indirect", "I'd like to know the colour of the cabinet", colour_of(CABINET)),
        _q(LV, "indirect", "how many chairs the living room has", count(CHAIRS), scope=None),
        _q(LV, "indirect", "tell me where the tv is, please", where(TVS)),
        _q(LV, "indirect", "the living room's tv: what colour is it?", colour_of(TVS), scope=None),
        _q(LV, "affordance", "where can I sit?", afford(SITTABLE, SITTABLE, "all")),
        _q(LV, "affordance", "where could I put my cup down?", afford(L(*SURFACES), PUT_PLACES, "any")),
        _q(LV, "affordance", "what can I drink from here?", afford(DRINKABLE, DRINKABLE, "all")),
        _q(LV, "affordance", "where can I keep my things?", afford(L(*STORAGE), STORE_PLACES | PUT_PLACES, "any")),
        _q(LV, "where_all", "where are all the chairs?", where_all(CHAIRS)),

        # ---------------- study
        _q(ST, "count", "how many chairs are there?", count(CHAIRS)),
        _q(ST, "count", "how many desks do you see?", count(DESKS)),
        _q(ST, "count", "how many fridges are in the study?", count(FRIDGE)),
        _q(ST, "count", "how many chairs are next to a desk?", count(rel(CHAIRS, "next to", DESKS))),
        _q(ST, "count", "how many things stand on the floor?", count(rel(THINGS, "on", FLOOR))),
        _q(ST, "count", "how many monitors are there?", count(TVS)),
        _q(ST, "count", "how many green chairs are there?", count(L("chair", colour="green"))),
        _q(ST, "exists", "is there a fridge in here?", exists(FRIDGE)),
        _q(ST, "exists", "is there a sofa?", exists(L("couch"))),
        _q(ST, "exists", "do you see any cups?", exists(CUPS)),
        _q(ST, "exists", "is there a desk?", exists(DESKS)),
        _q(ST, "exists", "is there a bed in the study?", exists(L("bed"))),
        _q(ST, "attribute", "what colour is the fridge?", colour_of(FRIDGE)),
        _q(ST, "attribute", "what colour are the desks?", colour_of(DESKS)),
        _q(ST, "attribute", "what colour is the monitor?", colour_of(TVS)),
        _q(ST, "attribute", "how tall is the fridge?", measure(FRIDGE, "height")),
        _q(ST, "attribute", "how big is the tv?", dims(TVS)),
        _q(ST, "where", "where is the fridge?", where(FRIDGE)),
        _q(ST, "where", "where's the tv?", where(TVS)),
        _q(ST, "relation", "what is next to the fridge?", objects(rel(THINGS, "next to", FRIDGE))),
        _q(ST, "relation", "is there anything on the desks?", exists(rel(THINGS, "on", DESKS))),
        _q(ST, "relation", "what's under the tv?", objects(rel(THINGS, "under", TVS))),
        _q(ST, "relation", "is the tv on a desk?", exists(rel(TVS, "on", DESKS))),
        _q(ST, "relation", "what is near the tv?", objects(rel(THINGS, "near", TVS))),
        _q(ST, "relation", "what's in the fridge?", objects(rel(THINGS, "in", FRIDGE))),
        _q(ST, "relation", "what's above the desks?", objects(rel(THINGS, "above", DESKS))),
        _q(ST, "relation", "is the fridge next to a desk?", exists(rel(FRIDGE, "next to", DESKS))),
        _q(ST, "distance", "how far is the fridge from the tv?", distance(FRIDGE, TVS)),
        _q(ST, "distance", "how far is the tv from the fridge in centimetres?", distance(TVS, FRIDGE)),
        _q(ST, "distance", "how far is the closest chair from the fridge?", distance(CHAIRS, FRIDGE)),
        _q(ST, "size", "is the fridge bigger than the tv?", bigger(FRIDGE, TVS)),
        _q(ST, "size", "which is bigger, the tv or the fridge?", pick_bigger(TVS, FRIDGE)),
        _q(ST, "size", "is the tv smaller than the fridge?", bigger(TVS, FRIDGE, smaller=True)),
        _q(ST, "negation", "are there at least three desks?", quantity(DESKS, ">=", 3)),
        _q(ST, "negation", "are there more than three chairs?", quantity(CHAIRS, ">", 3)),
        _q(ST, "negation", "is there exactly one fridge?", quantity(FRIDGE, "==", 1)),
        _q(ST, "negation", "is there anything on the floor besides the chairs?", exists(NOT_LABEL(rel(THINGS, "on", FLOOR), "chair"))),
        _q(ST, "negation", "what is next to the fridge other than the chair?", objects(NOT_LABEL(rel(THINGS, "next to", FRIDGE), "chair"))),
        _q(ST, "attr_set", "what is green?", objects(COL("green"))),
        _q(ST, "attr_set", "which things are blue?", objects(COL("blue"))),
        _q(ST, "attr_set", "what's grey in here?", objects(COL("grey"))),
        _q(ST, "article", "is there a chair next to the fridge?", exists(rel(CHAIRS, "next to", FRIDGE))),
        _q(ST, "article", "is the tv next to a chair?", exists(rel(TVS, "next to", CHAIRS))),
        _q(ST, "article", "is a desk next to the fridge?", exists(rel(DESKS, "next to", FRIDGE))),
        _q(ST, "indirect", "could you tell me how many desks there are?", count(DESKS)),
        _q(ST, "indirect", "I'd like to know what colour the fridge is", colour_of(FRIDGE)),
        _q(ST, "indirect", "how many chairs does the study have?", count(CHAIRS), scope=None),
        _q(ST, "indirect", "the study's desks: how many are there?", count(DESKS), scope=None),
        _q(ST, "indirect", "please list the things next to the fridge", objects(rel(THINGS, "next to", FRIDGE))),
        _q(ST, "affordance", "where can I sit?", afford(SITTABLE, SITTABLE, "all")),
        _q(ST, "affordance", "where could I work?", afford(DESKS, WORK_PLACES, "any")),
        _q(ST, "affordance", "where can I keep food cold?", afford(FRIDGE, FRIDGE, "all")),
        _q(ST, "affordance", "where can I put my laptop down?", afford(DESKS, PUT_PLACES, "any")),
        _q(ST, "affordance", "what can I drink from?", afford(DRINKABLE, DRINKABLE, "all")),
        _q(ST, "where_all", "where are all the chairs?", where_all(CHAIRS)),
        _q(ST, "where_all", "where are the desks?", where_all(DESKS)),

        # ---------------- the whole building (asked without --room)
        _q(B, "rooms", "in how many rooms is there a chair?", room_count(CHAIRS), scope=None),
        _q(B, "rooms", "how many rooms have a tv?", room_count(TVS), scope=None),
        _q(B, "rooms", "which room has the most chairs?", room_extreme(CHAIRS), scope=None),
        _q(B, "rooms", "which room has the most desks?", room_extreme(DESKS), scope=None),
        _q(B, "rooms", "which rooms have a fridge?", rooms_with(FRIDGE), scope=None),
        _q(B, "rooms", "which room has the fewest objects?", room_extreme(THINGS, most=False), scope=None),
        _q(B, "rooms", "what are the two rooms with the fewest objects?", rooms_fewest(THINGS, 2), scope=None),
        _q(B, "rooms", "which room contains the most things?", room_extreme(THINGS), scope=None),
        _q(B, "rooms", "in which rooms can I find cups?", rooms_with(CUPS), scope=None),
        _q(B, "rooms", "how many rooms are there?", room_total(), scope=None),
        _q(B, "rooms", "in how many rooms is there a sofa?", room_count(L("couch")), scope=None),
        _q(B, "rooms", "which room has more chairs, the kitchen or the study?",
           room_extreme(CHAIRS, among=("kitchen", "study")), scope=None),
        _q(B, "rooms", "how many chairs are there across all the rooms?", total_count(CHAIRS), scope=None),
        _q(B, "rooms", "which room has a tv but no chairs?",
           ((lambda w, r: Truth("rooms", {n for n, rm in w.rooms.items() if TVS(rm) and not CHAIRS(rm)})),
            "the rooms holding a tv and no chair"), scope=None),
    ]
    return qs


# ---------------------------------------------------------------------------------------------
# Judging an answer (the JSON of `sg3d ask --json`) against a truth

_NUM_WORDS = {"no": 0, "none": 0, "zero": 0, "one": 1, "a single": 1, "two": 2, "three": 3, "four": 4, "five": 5,
              "six": 6, "seven": 7, "eight": 8, "nine": 9, "ten": 10}


def _norm(text: str) -> str:
    return re.sub(r"\s+", " ", text.lower().replace("gray", "grey").replace("color", "colour"))


def named_ids(text: str, names: dict[str, str]) -> list[str]:
    """Ids whose printed names occur in `text`, in the order they occur (longest names first: a
    name inside a longer one's span is not counted, "dining table" in "the white cup on the
    dining table")."""
    out: list[str] = []
    for _, _, i in name_spans(_norm(text), names):
        if i not in out:
            out.append(i)
    return out


def value_ids(a: dict) -> set[str]:
    """The ids an answer's value and objects give."""
    got: set[str] = set()
    for part in (a.get("value"), a.get("objects")):
        items = part if isinstance(part, list) else [part]
        for x in items:
            if isinstance(x, dict) and isinstance(x.get("id"), str):
                got.add(x["id"])
    return got


def answer_ids(a: dict, names: dict[str, str]) -> set[str]:
    """The objects an answer names: its value's/objects' ids where it gives them, else the
    printed names in its text (after its first colon where it has one: "3 things next to the
    fridge: ..." names the fridge before the list)."""
    got = value_ids(a)
    if got:
        return got
    text = a.get("answer") or ""
    return set(named_ids(text.split(":", 1)[1] if ":" in text else text, names))


# A relation phrase in a "where" answer -> the oracle's relation word.
PHRASES = {"next to": "next to", "beside": "next to", "by": "next to", "near": "near", "close to": "near",
           "on top of": "on", "on": "on", "in": "in", "inside": "in", "under": "under", "underneath": "under",
           "beneath": "under", "below": "under", "above": "above", "over": "above"}
_PHRASE_RE = re.compile(r"\b(" + "|".join(sorted(map(re.escape, PHRASES), key=len, reverse=True)) + r")\b")


def name_spans(text: str, names: dict[str, str]) -> list[tuple[int, int, str]]:
    """(start, end, id) of printed names in lower-cased `text`, longest first, not overlapping."""
    taken = [False] * len(text)
    spans = []
    by_name: dict[str, list[str]] = {}
    for i, n in names.items():
        by_name.setdefault(n.lower(), []).append(i)
    for name in sorted(by_name, key=len, reverse=True):
        for m in re.finditer(r"(?<![\w])" + re.escape(name) + r"(?![\w])", text):
            if any(taken[m.start():m.end()]):
                continue
            for k in range(m.start(), m.end()):
                taken[k] = True
            spans += [(m.start(), m.end(), i) for i in by_name[name]]
    return sorted(spans)


def where_claims(clause: str, names: dict[str, str]) -> list[tuple[str, str]]:
    """(relation word, anchor id) for each object a where-clause places its subject by: the last
    relation phrase before each named object ("on A and B, next to C" -> on A, on B, next to C)."""
    spans = name_spans(clause, names)
    masked = list(clause)
    for s, e, _ in spans:
        masked[s:e] = " " * (e - s)
    phrases = [(m.start(), PHRASES[m.group(1)]) for m in _PHRASE_RE.finditer("".join(masked))]
    claims = []
    for s, _, i in spans:
        before = [w for p, w in phrases if p < s]
        if before:
            claims.append((before[-1], i))
    return claims


def holds(room_edges: set[tuple[str, str, str]], x: str, word: str, y: str) -> bool:
    for typ, way in RELATION_WORDS[word]:
        if (way == "fwd" and (x, typ, y) in room_edges) or (way == "back" and (y, typ, x) in room_edges):
            return True
    return False


def judge_where(text: str, truth: Truth, names: dict[str, str]) -> bool:
    """Every subject gets a clause ("X is on A, next to B, in the kitchen"; clauses split at ';');
    each clause is right when it places its subject by at least one object and every placement
    it states holds in the graph (direction included: "the cabinet is on the vase" is wrong
    when the vase is on the cabinet); a subject with no placement edge is right when its room
    is named."""
    subjects, edges, room = truth.value, truth.extra["edges"], truth.extra["room"]
    if not subjects:
        return False
    clauses = [c for c in _norm(text).split(";") if c.strip()]
    parsed = []
    for c in clauses:
        m = re.search(r"\b(?:is|are)\b", c)
        head, rest = (c[:m.start()], c[m.end():]) if m else ("", c)
        parsed.append((head.strip().removeprefix("the ").strip(), rest))
    # which subject each clause is about: its printed name, else the one its head starts (the
    # answer may drop a name's "on the shelf" once it says where the thing is)
    owner: dict[int, str] = {}
    if len(subjects) == 1 and len(parsed) == 1:
        owner[0] = next(iter(subjects))
    else:
        left = set(subjects)
        for exact in (True, False):
            for k, (head, _) in enumerate(parsed):
                if k in owner:
                    continue
                hits = [s for s in left if (names.get(s, "").lower() == head if exact
                                            else head and names.get(s, "").lower().startswith(head))]
                if len(hits) == 1 or (hits and not exact):
                    owner[k] = sorted(hits)[0]
                    left.discard(owner[k])
    if set(owner.values()) != set(subjects):
        return False
    for k, s in owner.items():
        claims = where_claims(parsed[k][1], {i: n for i, n in names.items() if i != s})
        if not truth.extra["anchors"][s]:
            if room not in rooms_in(parsed[k][1]):
                return False
            continue
        if not claims or not all(holds(edges, s, w, y) for w, y in claims):
            return False
    return True


def lengths_m(text: str) -> list[float]:
    """Every length written in the text, in metres ("1.62 m", "70x47 cm", "162 cm")."""
    out = []
    for m in re.finditer(r"((?:\d+(?:\.\d+)?\s*[x×]\s*)*\d+(?:\.\d+)?)\s*(mm|cm|m|metres?|meters?|centimetres?|centimeters?)\b",
                         text.lower()):
        unit = m.group(2)
        scale = 0.001 if unit == "mm" else 0.01 if unit.startswith("c") else 1.0
        out += [float(x) * scale for x in re.split(r"\s*[x×]\s*", m.group(1))]
    return out


def first_number(text: str) -> Optional[int]:
    t = _norm(text)
    m = re.search(r"\b(\d+)\b", t)
    word = None
    for w, n in _NUM_WORDS.items():
        wm = re.search(r"\b" + w + r"\b", t)
        if wm and (word is None or wm.start() < word[0]):
            word = (wm.start(), n)
    if m and (word is None or m.start() < word[0]):
        return int(m.group(1))
    return word[1] if word else None


def yes_no(a: dict) -> Optional[bool]:
    v = a.get("value")
    if isinstance(v, bool):
        return v
    t = _norm(a.get("answer") or "").lstrip()
    if re.match(r"yes\b", t):
        return True
    if re.match(r"no\b", t) or "have not found" in t or "haven't found" in t:
        return False
    return None


def says_nothing(a: dict) -> bool:
    t = _norm(a.get("answer") or "")
    return bool(re.search(r"\b(nothing|none|no\b|not found|have not found|0 )", t)) or a.get("value") in ([], 0, None, False)


def rooms_in(text: str) -> list[str]:
    t = _norm(text)
    hits = []
    for name, pattern in ROOM_WORDS.items():
        m = re.search(r"\b" + pattern + r"\b", t)
        if m:
            hits.append((m.start(), name))
    return [n for _, n in sorted(hits)]


def judge(a: dict, truth: Truth, names: dict[str, str]) -> bool:
    """Whether a (not refused) answer holds the truth's fact."""
    text = a.get("answer") or ""
    v = a.get("value")
    k = truth.kind
    if k == "count":
        n = v if isinstance(v, int) and not isinstance(v, bool) else first_number(text)
        return n == truth.value
    if k == "yesno":
        return yes_no(a) is truth.value
    if k == "colour":
        words = set(re.findall(r"[a-z]+", _norm(text)))
        return truth.value is not None and truth.value in words
    if k == "length":
        if truth.value is None:
            return False
        nums = lengths_m(text) + ([float(v)] if isinstance(v, (int, float)) and not isinstance(v, bool) else [])
        return any(abs(x - truth.value) <= truth.extra["tol"] for x in nums)
    if k == "dims":
        if not truth.value:
            return False
        nums = lengths_m(text)
        if isinstance(v, list) and all(isinstance(x, (int, float)) for x in v):
            nums += [float(x) for x in v]
        if all(any(abs(x - d) <= 0.05 for x in nums) for d in truth.value):
            return True
        volume = truth.value[0] * truth.value[1] * truth.value[2]
        m = re.search(r"(\d+(?:\.\d+)?)\s*m\s*(?:\^3|³)", text)
        return m is not None and abs(float(m.group(1)) - volume) <= 0.1 * volume
    if k == "objects":
        if not truth.value:
            return not value_ids(a) and says_nothing(a)
        return answer_ids(a, names) == truth.value
    if k == "afford":
        got = answer_ids(a, names)
        core, allowed = truth.value, truth.extra["allowed"]
        if not core:
            return not value_ids(a) and says_nothing(a)
        covered = core <= got if truth.extra["need"] == "all" else bool(core & got)
        return covered and got <= allowed
    if k in ("where", "where_all"):
        return judge_where(text, truth, names)
    if k == "pick":
        got = answer_ids(a, names)
        if len(got) == 1:
            return got == {truth.value}
        order = [i for i in named_ids(text, names) if i in truth.extra["candidates"]]
        return bool(order) and order[0] == truth.value
    if k == "room":
        if isinstance(v, dict) and isinstance(v.get("room"), str):
            return v["room"].split("/", 1)[-1] == truth.value
        found = rooms_in(text)
        return bool(found) and found[0] == truth.value
    if k == "rooms":
        listed = set(rooms_in(text))
        if not truth.value:
            return not listed and says_nothing(a)
        return listed == truth.value
    raise ValueError(f"unknown truth kind {k}")


def refused_word(a: dict) -> str:
    """The word a refusal names ('...' in its text), or the reason when it names none."""
    text = a.get("answer") or ""
    m = re.search(r"'([^']+)'", text)
    if m:
        return m.group(1)
    return "(" + re.split(r"[;:]", text, maxsplit=1)[0].strip()[:60] + ")"


# ---------------------------------------------------------------------------------------------
# Running


def ask_all(store, world: World, qs: list[Q]) -> list[dict]:
    from sg3d.app.ask import ask
    from sg3d.app.errors import AppError

    names_all = world.names()
    rows = []
    for q in qs:
        room = world.rooms.get(q.room) if q.room != "building" else None
        truth = q.oracle(world, room or next(iter(world.rooms.values())))
        # printed names are unique within a room only ("white object 3" may be in two rooms): an
        # answer about one room (asked of it, or naming it in words) is read with that room's names
        about = q.scope or (q.room if q.room in world.rooms else None)
        names = names_all if about is None else {o["id"]: o["name"] for o in world.rooms[about].objects}
        try:
            a = ask(store, q.text, room=q.scope).to_json()
        except AppError as exc:
            a = {"ok": False, "form": "error", "answer": str(exc), "value": None, "objects": []}
        if not a.get("ok"):
            verdict, word = "refused", refused_word(a)
        else:
            verdict, word = ("right" if judge(a, truth, names) else "wrong"), None
        rows.append({"room": q.room, "form": q.form, "question": q.text, "scope": q.scope or "(building)",
                     "answer": re.sub(r"\s+", " ", a.get("answer") or ""), "answer_form": a.get("form"),
                     "verdict": verdict, "refused_word": word, "truth": truth.show(names_all), "rule": q.rule})
    return rows


def summary(rows: list[dict]) -> dict:
    def tally(key):
        out: dict[str, Counter] = {}
        for r in rows:
            out.setdefault(r[key], Counter())[r["verdict"]] += 1
        return out
    right = sum(r["verdict"] == "right" for r in rows)
    return {"questions": len(rows), "right": right,
            "wrong": sum(r["verdict"] == "wrong" for r in rows),
            "refused": sum(r["verdict"] == "refused" for r in rows),
            "percent_right": round(100.0 * right / len(rows), 1) if rows else 0.0,
            "by_form": {k: dict(v) for k, v in tally("form").items()},
            "by_room": {k: dict(v) for k, v in tally("room").items()}}


def table(rows: list[dict]) -> str:
    s = summary(rows)
    lines = ["| group | questions | right | wrong | refused |", "|---|---|---|---|---|"]
    for title, key, order in (("form", "by_form", list(FORMS)), ("room", "by_room", ["kitchen", "livingroom", "study", "building"])):
        for k in order:
            c = s[key].get(k)
            if c:
                n = sum(c.values())
                lines.append(f"| {title}: {k} | {n} | {c.get('right', 0)} | {c.get('wrong', 0)} | {c.get('refused', 0)} |")
    lines.append(f"| **all** | {s['questions']} | {s['right']} | {s['wrong']} | {s['refused']} |")
    lines.append("")
    lines.append(f"overall: {s['right']} of {s['questions']} right ({s['percent_right']} %), "
                 f"{s['wrong']} wrong, {s['refused']} refused")
    refused = [r for r in rows if r["verdict"] == "refused"]
    if refused:
        lines += ["", "refused (the word named):"]
        lines += [f"- [{r['room']}/{r['form']}] {r['question']!r} -> {r['refused_word']}" for r in refused]
    wrong = [r for r in rows if r["verdict"] == "wrong"]
    if wrong:
        lines += ["", "wrong (answer | oracle):"]
        lines += [f"- [{r['room']}/{r['form']}] {r['question']!r} -> {r['answer'][:160]} | {r['truth'][:120]}" for r in wrong]
    return "\n".join(lines)


MD_HEADER = """# Paraphrases: ordinary users' questions on three rooms

An independent benchmark of `sg3d ask`, written by someone who did not read the question
reader's code, grammar or tests (only the README, the docs' overviews and the format of
benchmarks/questions_kitchen.py), from a brief of the question forms the reader should cover
and from what the three built rooms hold (`sg3d cypher`, the stored objects and edges). The
questions are phrased as people phrase them, not as the grammar expects.

Run: `python -m benchmarks.paraphrases [--keep-home DIR | --home DIR] [--json] [--md FILE]`
builds the kitchen (7-Scenes red kitchen), the living room (Open3D living-room micro) and the
study (3DMatch study room, fragment-1 then fragment-2) into one building `default` of a scratch
store (or reuses `--home`), asks every question through `sg3d.app.ask.ask` (what `sg3d ask`,
`POST /ask` and MCP call), and judges each answer by its oracle. Regenerate this page with
`python -m benchmarks.paraphrases --home DIR --md benchmarks/paraphrases.md`.

## How answers are judged

Every oracle is computed on each run from the stored graph (templates `object_all`,
`relation_all`, `vqa_rooms_all`; printed names from the store's naming, used only to find the
objects an answer names); no expected answer is typed in. "Things"/"objects" are the object
layer (the floor, walls, counters and shelves are structure, asked for by name). Labels are the
stored ones: a question's "fridge" is `refrigerator`, "sofa" `couch`, "monitor"/"television"
`tv`, "mug" `cup`, "armchair" `chair`, "table" the kitchen's `dining table`.

- **right**: the answer holds the oracle's fact: the count (the answer's value, else its first
  number); yes/no (value, or the text's leading yes/no, "I have not found" = no); exactly the
  oracle's set of objects (ids in the answer's value, else the printed names after its first
  colon; an empty set wants "nothing"/"not found" and no object); the colour word; a distance
  within 10 cm or a size within 5 cm (m, cm or mm in the text); the room or set of rooms named.
- **wrong**: it answers something else, including an answer that silently drops a word (e.g. a
  general storage list for "keep food cold").
- **refused**: `ok` is false; the word the refusal quotes is recorded.

Relation words, as the oracle reads the stored edges (X is the thing asked about):
on = X -ON-> Y; in = X -IN-> Y; next to = NEXT_TO either way; near = NEAR or NEXT_TO either way
(as docs/model.md defines it); under/below = X -UNDER|BELOW-> Y or Y -ABOVE-> X (beneath,
touching or not); above = X -ABOVE-> Y or Y -BELOW|UNDER-> X (over, not resting on it).
"Where is X" is right when the answer places X by at least one object and every placement it
states holds in that direction ("the cabinet is on the vase" is wrong when the vase is on the
cabinet); "where are all the X" wants such a clause for every X. Size comparisons use the stored
volume; width is the stored size's first (width) component, length the larger horizontal one.
Affordances: sit = chair/couch/bench/bed/toilet/stool; drink from = cup/wine glass/bottle;
put things down = tables, desks, counters, cabinets, shelves, surfaces; store = cabinets, shelves,
refrigerators, drawers, bookcases; work at = desks, tables, counters. "The X" is used only where
the room holds one X (or one X of that colour); "a X" means any X.

"""


HELDOUT_MARK = "## Held-out set"


def _revision() -> str:
    """The checkout's commit (read-only: `git rev-parse`), or 'unknown'."""
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, capture_output=True, text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def markdown(rows: list[dict]) -> str:
    s = summary(rows)
    import datetime

    when = datetime.date.today().isoformat()
    out = [MD_HEADER + f"## Results\n\nThe reader in the working tree at commit {_revision()} (with any uncommitted "
           f"changes), {when}, default builds:\n\n" + table(rows).split("\n\nrefused")[0].split("\n\nwrong")[0], "",
           "## Questions, oracle rules and results", "",
           f"{s['right']} of {s['questions']} right ({s['percent_right']} %), {s['wrong']} wrong, {s['refused']} refused.", ""]
    for form, title in FORMS.items():
        group = [r for r in rows if r["form"] == form]
        if not group:
            continue
        out += [f"### {title}", "", "| room | asked with | question | oracle rule | oracle says | answer | verdict |",
                "|---|---|---|---|---|---|---|"]
        for room in ("kitchen", "livingroom", "study", "building"):
            for r in (x for x in group if x["room"] == room):
                verdict = r["verdict"] + (f" ('{r['refused_word']}')" if r["refused_word"] else "")
                cells = [room, "--room " + r["scope"] if r["scope"] != "(building)" else "no --room", r["question"],
                         r["rule"], r["truth"], r["answer"][:200], verdict]
                out.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
        out.append("")
    return "\n".join(out)


def build(home: Path) -> None:
    env = {**os.environ, "SG3D_HOME": str(home)}
    for room, seqs in ROOMS.items():
        for seq in seqs:
            if not seq.exists():
                raise SystemExit(f"{seq} is not there (set SG3D_SHARED to the folder holding data/)")
            out = subprocess.run([sys.executable, "-m", "sg3d", "build", str(seq), "--room", room, "--building", BUILDING,
                                  "--json"], env=env, capture_output=True, text=True)
            if out.returncode != 0:
                raise SystemExit(f"sg3d build {seq} --room {room} failed: {out.stderr.strip()[-500:]}")
            print(f"built {seq.name} into {room}", file=sys.stderr)


def open_reader(home: Path):
    from sg3d.app.stores import reader
    from sg3d.settings import Settings

    return reader(Settings.from_options(home=str(home)))


def run(home: Path, qs: Optional[list[Q]] = None) -> list[dict]:
    """Ask `qs` (default: this module's questions) of the rooms in `home` and judge them."""
    store = open_reader(home)
    world = World.load(store)
    missing = [n for n in ROOMS if n not in world.rooms]
    if missing:
        raise SystemExit(f"the store in {home} lacks room(s) {', '.join(missing)}: build them, or leave out --home")
    return ask_all(store, world, questions() if qs is None else qs)


def arguments(description: str) -> argparse.ArgumentParser:
    """The options every question set's command takes (this one, the held-out sets)."""
    ap = argparse.ArgumentParser(description=description)
    where_ = ap.add_mutually_exclusive_group()
    where_.add_argument("--keep-home", type=Path, help="build the rooms into this SG3D_HOME and keep it")
    where_.add_argument("--home", type=Path, help="reuse this SG3D_HOME, which already holds the three rooms")
    ap.add_argument("--json", action="store_true", help="one JSON object per question, then the summary")
    return ap


def ask_set(args, qs: Optional[list[Q]], prefix: str) -> list[dict]:
    """Ask a question set of the rooms of `--home`, or of rooms built into `--keep-home` or a
    scratch home (whose store is stopped afterwards, and the scratch home removed)."""
    scratch = None
    if args.home:
        home = args.home
    else:
        home = args.keep_home or Path(scratch := tempfile.mkdtemp(prefix=prefix))
        home.mkdir(parents=True, exist_ok=True)
    os.environ["SG3D_HOME"] = str(home)
    try:
        if not args.home:
            build(home)
        return run(home, qs)
    finally:
        if not args.home:           # the store this run started: stop it (a kept home restarts on demand)
            subprocess.run([sys.executable, "-m", "sg3d", "db", "stop"], env={**os.environ, "SG3D_HOME": str(home)},
                           capture_output=True)
        if scratch:
            shutil.rmtree(scratch, ignore_errors=True)


def report(rows: list[dict], as_json: bool) -> None:
    """The table, or one JSON object per question and the summary."""
    if as_json:
        for r in rows:
            print(json.dumps(r))
        print(json.dumps({"summary": summary(rows)}))
    else:
        print(table(rows))


def main(argv=None) -> int:
    ap = arguments(__doc__.splitlines()[0])
    ap.add_argument("--md", type=Path, help="also write the questions, oracle rules and results (markdown) here")
    args = ap.parse_args(argv)
    rows = ask_set(args, None, "sg3d-paraphrases-")
    report(rows, args.json)
    if args.md:
        # keep a hand-written held-out section (benchmarks/paraphrases_heldout.py) at the page's end
        kept = args.md.read_text().partition(HELDOUT_MARK)[1:] if args.md.exists() else ("", "")
        args.md.write_text(markdown(rows) + ("\n" + "".join(kept) if kept[0] else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
