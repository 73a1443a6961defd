"""One naming scheme for stored objects, used by ask, plan, show, export and the eval report.

A person reads "the white cup on the dining table" or "chair 2", not "o-367faaad247349d0".
Names are derived from what is stored, in this order, each step only when the previous one does
not tell the objects of one label in one room apart:

    1. the label                    "keyboard"
    2. colour + label               "white cup"
    3. colour + label + support     "white cup on the dining table"  (the object it is ON/IN)
    4. label + number               "chair 2"

An unnamed object (label "object", found from geometry) is called by its colour, "white
object", then steps 3 and 4 among unnamed objects of that colour ("white object on the dining
table", "white object 2"); lists add its shape and size ("flat, about 30x22 cm"). The shape is
not part of the name, so every caller (whatever fields it reads) prints the same name.

Numbers count the objects of the label in the room in a stable order: the frame that first saw
the object, then its position (rounded to centimetres), never the id (a hash). Re-building the
same data gives the same names; extending a room appends later-seen objects at the end. When one
answer spans rooms and a name occurs in more than one, " in the <room>" is added.
Ids stay available in --json / --explain; names are for people.
"""
from __future__ import annotations

from typing import Iterable, Optional

from sg3d.core.shape import SAID
from sg3d.core.stored import Row, StoredGraph

SUPPORT_TYPES = ("ON", "IN")


def stable_key(o: dict) -> tuple:
    """The order objects of one label are numbered in: first frame seen, then position."""
    pos = tuple(round(float(o[k]), 2) if o.get(k) is not None else 0.0 for k in ("x", "y", "z"))
    first = o.get("first_frame")
    return (int(first) if first is not None else 1 << 30, pos, str(o.get("id")))


def room_name(room: Optional[str]) -> str:
    return (room or "").split("/", 1)[-1]


def support_phrase(rel: str, label: str) -> str:
    return f"{'in' if rel == 'IN' else 'on'} the {label}"


def supports_from_edges(edges: Iterable[dict], labels: dict[str, str]) -> dict[str, str]:
    """id -> "on the <label>" / "in the <label>": what the object stands on or is in, from edges
    {s, type, o, score} (the best-scored one; ties by label)."""
    out: dict[str, tuple[float, str]] = {}
    for e in edges:
        # "on the object" tells no one which: an unnamed support does not name what it holds
        if e.get("type") in SUPPORT_TYPES and e.get("o") in labels and labels[e["o"]] != "object":
            cand = (float(e.get("score") or 0.0), support_phrase(e["type"], labels[e["o"]]))
            if e["s"] not in out or (cand[0], out[e["s"]][1]) > (out[e["s"]][0], cand[1]):
                out[e["s"]] = cand
    return {k: v for k, (_, v) in out.items()}


def looks(o: dict) -> str:
    """The kind an unnamed object is named among: "white object" (its colour)."""
    return " ".join(x for x in (o.get("colour"), "object") if x)


def describe_unnamed(o: dict) -> str:
    """"flat, about 30x22 cm": an unnamed object's shape word and its two largest box sides."""
    size = sorted((float(v) for v in (o.get("size") or [])), reverse=True)[:2]
    bits = [SAID.get(o["shape"], o["shape"])] if o.get("shape") else []
    if len(size) == 2:
        bits.append("about " + "x".join(f"{v * 100:.0f}" for v in size) + " cm")
    return ", ".join(bits)


def _kind(o: dict) -> str:
    """Objects are named among those of one kind: their label, or for unnamed ones their colour."""
    label = o.get("label") or "object"
    return looks(o) if label == "object" else label


def object_names(objects: Iterable[dict], supports: Optional[dict[str, str]] = None) -> dict[str, str]:
    """{id: readable name} for every object given (dicts with id, label and, when known, colour,
    room, x/y/z, first_frame and support: "on the <label>" for what it is ON/IN). Pass every object of the
    labels concerned in their rooms, so the names are the same whatever subset is shown."""
    objs = list(objects)
    supports = dict(supports or {})
    for o in objs:
        if o.get("support") and o["id"] not in supports:
            supports[o["id"]] = o["support"]
    groups: dict[tuple[str, str], list[Row]] = {}
    for o in objs:
        groups.setdefault((o.get("room") or "", _kind(o)), []).append(o)
    names: dict[str, str] = {}
    for (_, label), group in groups.items():
        group.sort(key=stable_key)
        if len(group) == 1:
            names[group[0]["id"]] = label
            continue
        colours = [o.get("colour") for o in group]
        # objects their colour does not single out; where they are may (among themselves)
        ambiguous = [o for o in group if not (o.get("colour") and colours.count(o["colour"]) == 1)]
        placed = [(o.get("colour"), supports.get(o["id"])) for o in ambiguous]
        for i, o in enumerate(group, 1):
            colour, support = o.get("colour"), supports.get(o["id"])
            if label.endswith(" object"):     # unnamed: the look already says the colour
                names[o["id"]] = f"{label} {support}" if len(ambiguous) > 1 and support and \
                    [supports.get(x["id"]) for x in group].count(support) == 1 else f"{label} {i}"
            elif o not in ambiguous:
                names[o["id"]] = f"{colour} {label}"
            elif len(ambiguous) > 1 and support and placed.count((colour, support)) == 1:
                names[o["id"]] = " ".join(x for x in (colour, label, support) if x)
            else:
                names[o["id"]] = f"{label} {i}"
    rooms_of: dict[str, set] = {}
    for o in objs:
        rooms_of.setdefault(names[o["id"]], set()).add(o.get("room") or "")
    for o in objs:
        if len(rooms_of[names[o["id"]]]) > 1:
            names[o["id"]] += f" in the {room_name(o.get('room'))}"
    return names


def names_in_store(read, objects: Iterable[dict]) -> dict[str, str]:
    """{id: name} for the given stored objects (dicts with id, label, room), named among every
    object of their labels in their rooms. `read(template, **params)` runs a read template."""
    objs = [o for o in objects if o.get("id") and o.get("label")]
    if not objs:
        return {}
    rooms = sorted({o["room"] for o in objs if o.get("room")})
    labels = sorted({o["label"] for o in objs})
    rows = read("naming_objects", rooms=rooms, labels=labels, support_types=list(SUPPORT_TYPES)) if rooms else []
    everyone: dict[str, dict] = {}
    edges = []
    for r in rows:
        everyone.setdefault(r["id"], {k: r.get(k) for k in ("id", "label", "colour", "room", "x", "y", "z",
                                                            "first_frame", "shape", "size")})
        if r.get("support_type"):
            edges.append({"s": r["id"], "type": r["support_type"], "o": r["support_label"],
                          "score": r.get("support_score")})
    for o in objs:      # objects outside any room (none today) are still named
        everyone.setdefault(o["id"], o)
    supports = supports_from_edges(edges, {e["o"]: e["o"] for e in edges})
    names = object_names(everyone.values(), supports)
    return {o["id"]: names[o["id"]] for o in objs}


def name_graph(graph: StoredGraph) -> StoredGraph:
    """The exported graph with each node's readable name."""
    objs = [{**n.as_json(), "room": n.room or n.room_name or ""} for n in graph.nodes]
    labels = {n.id: n.label or "object" for n in graph.nodes}
    names = object_names(objs, supports_from_edges([e.as_json() for e in graph.edges], labels))
    return graph.named(names)
