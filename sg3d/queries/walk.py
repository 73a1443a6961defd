"""Questions over the rooms found in a walk (`sg3d build --rooms auto`, the places layer): which
rooms a doorway joins to a room and what they hold, the way from one room to another, which room
holds a kind.

A room is named as stored ("room 2", or the name `sg3d rooms rename` gave it) or by its guessed
kind ("the kitchen"). A kind is a guess from what the room holds (`kind_guess`, with its
evidence), never a fact: an answer that found a room by its guess says so, with the evidence.
"""
from __future__ import annotations

from typing import Optional

from sg3d.core.stored import Row
from sg3d.queries.logic import NP
from sg3d.queries.place_names import match_name, squeezed
from sg3d.queries.sets import Unanswerable
from sg3d.queries.answer.wording import plural


def walk_layer(a) -> list[Row]:
    """The rooms of the walks in scope (cypher/vqa_walk_rooms): [] when no recorded room in scope
    was split into rooms."""
    rows = a.run.read("vqa_walk_rooms", building=a.ev.building)
    if a.scene is not None and a.scene.rooms is not None:
        rows = [r for r in rows if r["walk"] in a.scene.rooms]
    return rows


def said_name(a, np: NP) -> str:
    """The words of a room's name as the user said them: a multi-word name the reader replaced
    by one word (reader.reading.GrammarReader) is given back."""
    text = np.text()
    back = getattr(a.ev.is_room, "said", None)
    return back(text) if back is not None else text


def named(layer: list[Row], said: str) -> tuple[list[Row], bool]:
    """Rule "a room is named by its name, else by its guessed kind": (the rooms `said` names,
    whether they were found by a guess). The stored names first (case, spaces and a small typo
    set aside, sg3d/queries/place_names.py); else every room whose guessed kind is the words
    ("kitchen", "the living room"); ([], False) when neither."""
    hit = match_name(said, {r["name"] for r in layer})
    if hit is not None:
        return [r for r in layer if r["name"] == hit], False
    want = squeezed(said)
    guessed = [r for r in layer if r.get("kind_guess") and squeezed(r["kind_guess"]) in (want, want + "room")]
    return guessed, bool(guessed)


def room_words(w: dict, guessed: bool = False) -> str:
    """A room in an answer: its name and its guessed kind, said as a guess with its evidence:
    "room 2 (looks like a kitchen: refrigerator, sink)"; `guessed` (the question named the room by
    that kind): "room 2 (the kitchen by a guess from what it holds: refrigerator, sink)"."""
    kind = w.get("kind_guess")
    if not kind:
        return w["name"]
    evidence = ", ".join(w.get("kind_evidence") or [])
    if guessed:
        return f"{w['name']} (the {kind} by a guess from what it holds: {evidence})"
    return f"{w['name']} (looks like {'an' if kind[:1] in 'aeiou' else 'a'} {kind}: {evidence})"


def resolve_rooms(a, np: NP, layer: list[Row]) -> tuple[list[Row], bool]:
    """The walk rooms a noun phrase names; Unanswerable naming the rooms there are otherwise."""
    said = said_name(a, np)
    rooms, guessed = named(layer, said)
    if not rooms:
        known = sorted({r["name"] for r in layer})
        kinds = sorted({r["kind_guess"] for r in layer if r.get("kind_guess")})
        raise Unanswerable(f"no room found in the walk is called '{said}' or looks like one (rooms: "
                           f"{', '.join(known)}" + (f"; guessed kinds: {', '.join(kinds)}" if kinds else "") + ")")
    return rooms, guessed


def _holding(a, w: dict) -> str:
    objs = [dict(o) for o in w["objects"] if (o.get("layer") or "object") != "structure"]
    return a.listing(objs) if objs else "nothing sg3d named"


def op_walk_next(a, np: NP, layer: list[Row], hold: bool):
    """"what rooms are next to the kitchen", "what is in the room next to the kitchen": the rooms
    a doorway joins to the named one (CONNECTED through a Doorway), each with the doorway's width,
    and with `hold` what each room holds."""
    rooms, guessed = resolve_rooms(a, np, layer)
    by_id = {r["id"]: r for r in layer}
    mine = {r["id"] for r in rooms}
    seen: dict[str, dict] = {}
    for r in rooms:
        for d in r["doorways"]:
            if d["room"] not in mine and d["room"] in by_id:
                seen.setdefault(d["room"], d)
    asked = " and ".join(room_words(r, guessed) for r in rooms)
    if not seen:
        return f"none: no doorway was found from {asked}", [], []
    parts, value, rows = [], [], []
    for rid, d in sorted(seen.items(), key=lambda kv: by_id[kv[0]]["name"]):
        w = by_id[rid]
        text = f"{room_words(w)} through a doorway {d['width']:.2f} m wide"
        if hold:
            text += f", holding {_holding(a, w)}"
            rows += [o for o in w["objects"] if (o.get("layer") or "object") != "structure"]
        parts.append(text)
        value.append({"room": w["name"], "walk": w["walk"], "doorway": d["doorway"], "width": d["width"],
                      "objects": [o["id"] for o in w["objects"]]})
    return f"next to {asked}: " + "; ".join(parts), value, rows


def _graph(layer: list[Row]):
    """The rooms and doorways as one graph (networkx): a room's middle to a doorway's middle is
    an edge as long as the straight line between them."""
    import networkx as nx
    import numpy as np

    g = nx.Graph()
    by_id = {r["id"]: r for r in layer}
    for r in layer:
        g.add_node(r["id"])
        for d in r["doorways"]:
            if d["room"] not in by_id:
                continue
            g.add_edge(r["id"], d["doorway"],
                       weight=float(np.linalg.norm(np.subtract([r["x"], r["y"], r["z"]], [d["x"], d["y"], d["z"]]))))
    return g


def shortest_way(layer: list[Row], starts: list[Row], goals: list[Row]) -> Optional[tuple[float, list[str]]]:
    """Rule "the way is the shortest walk over the room/doorway graph": (metres, the room and
    doorway ids in order) from any of `starts` to any of `goals` along room middle -> doorway
    middle -> room middle (Dijkstra); None when no doorway joins them."""
    import networkx as nx

    g = _graph(layer)
    best: Optional[tuple[float, list[str]]] = None
    for s in starts:
        for t in goals:
            try:
                length, path = nx.single_source_dijkstra(g, s["id"], t["id"], weight="weight")
            except nx.NetworkXNoPath:
                continue
            if best is None or length < best[0]:
                best = (float(length), list(path))
    return best


def op_walk_route(a, start: NP, goal: NP, layer: list[Row]):
    """"how do I get from the kitchen to the bedroom": the rooms and doorways on the shortest
    way (`shortest_way`), each doorway with its middle and width."""
    starts, s_guess = resolve_rooms(a, start, layer)
    goals, g_guess = resolve_rooms(a, goal, layer)
    by_id = {r["id"]: r for r in layer}
    doors = {d["doorway"]: d for r in layer for d in r["doorways"]}
    if {r["id"] for r in starts} & {r["id"] for r in goals}:
        shared = next(r for r in starts if r in goals)
        return f"you are already there: {room_words(shared, s_guess or g_guess)} is where you start and end", [], []
    found = shortest_way(layer, starts, goals)
    said_from = " or ".join(room_words(r, s_guess) for r in starts)
    said_to = " or ".join(room_words(r, g_guess) for r in goals)
    if found is None:
        return f"no way found: no doorway seen in the walk joins {said_from} to {said_to}", [], []
    metres, path = found
    steps, value = [], []
    for k in range(1, len(path) - 1, 2):
        d, nxt = doors[path[k]], by_id[path[k + 1]]
        steps.append(f"through the doorway at ({d['x']:.2f}, {d['y']:.2f}, {d['z']:.2f}), {d['width']:.2f} m wide, "
                     f"into {room_words(nxt, g_guess and nxt in goals)}")
        value.append({"doorway": d["doorway"], "x": d["x"], "y": d["y"], "z": d["z"], "width": d["width"],
                      "into": nxt["name"]})
    first = by_id[path[0]]
    n = len(steps)
    return (f"from {room_words(first, s_guess)}: " + "; then ".join(steps)
            + f" ({n} {plural('doorway', n)}, about {metres:.1f} m between the rooms' middles)"), value, []


def rooms_of_objects(a, rows: list[Row], layer: list[Row]) -> dict[str, dict]:
    """object id -> the walk room holding it, for objects the places layer placed."""
    wanted = {o["id"] for o in rows}
    return {o["id"]: w for w in layer for o in w["objects"] if o["id"] in wanted}


def not_detected(resolved: list) -> Optional[str]:
    """Rule "what sg3d cannot see is not said to be absent": the words of the first lacking kind
    that names no label sg3d stores (the lexicon reads it as unknown, e.g. a door: neither the
    detector nor the structure step finds doors); None when every one is a known label."""
    for r in resolved:
        if r.kind == "unknown":
            return r.np.text()
    return None


def op_walk_rooms_lacking(a, wanted: list[NP], lacking: list[NP], layer: list[Row]):
    """"which rooms have no fridge", "which rooms have a bed but no tv" over the rooms of a walk;
    a lacking kind sg3d never detects is said so, not answered as absent everywhere."""
    if not wanted and asks_windows(a, lacking):
        return op_walk_windows(a, lacking=True)
    resolved = [a.ev.resolved(np) for np in lacking]
    blind = not_detected(resolved)
    names = ", ".join(room_words(w) for w in sorted(layer, key=lambda w: (w["walk"], w["name"])))
    if blind is not None:
        return (f"I cannot tell: sg3d does not detect {plural(blind, 2)} (no label it gives covers "
                f"'{blind}'), so none is stored in any room, with or without one; the rooms: {names}"), None, []

    def has(w: dict, np: NP) -> bool:
        ids = {o["id"] for o in a.ev.members(np)}
        return any(o["id"] in ids for o in w["objects"])

    keep = [w for w in layer if all(has(w, np) for np in wanted) and not any(has(w, np) for np in lacking)]
    said = " or ".join(a.phrase(np, 1) for np in lacking)
    if not keep:
        return f"none: every room holds {said}", [], []
    return ", ".join(room_words(w) for w in keep) + f"; no {said} in {'it' if len(keep) == 1 else 'them'}", \
        [{"room": w["name"], "walk": w["walk"]} for w in keep], []


# Rule "no window seen is not no window": a room at least this share of whose outline no seen wall
# closes (`sg3d.ingest.places.rooms.unseen_outline`) may have a window the walk never looked at.
UNSEEN_OUTLINE_SHARE = 0.15


def window_words(win: dict) -> str:
    """A window in an answer: its width along the wall and its height (its box, gravity frame)."""
    sx, sy, sz = (float(v) for v in (win.get("size") or [0.0, 0.0, 0.0]))
    return f"{max(sx, sy):.1f} m wide, {sz:.1f} m tall"


def op_walk_windows(a, lacking: bool) -> tuple[str, list, list]:
    """"which rooms have no window" / "which rooms have a window" over the rooms of a walk
    (cypher/vqa_walk_windows: the windows IN each room, found as holes in the walls), said by
    `windows_answer`."""
    rows = a.run.read("vqa_walk_windows", building=a.ev.building)
    if a.scene is not None and a.scene.rooms is not None:
        rows = [r for r in rows if r["walk"] in a.scene.rooms]
    text, value = windows_answer(rows, lacking)
    return text, value, []


def windows_answer(rows: list[Row], lacking: bool) -> tuple[str, list]:
    """The rooms with a window (each with its windows' sizes), or without one: a room without
    one whose outline was partly never seen (at least UNSEEN_OUTLINE_SHARE) is said to have no
    window seen, never no window."""
    rows = sorted(rows, key=lambda w: (w["walk"], w["name"]))
    if not lacking:
        keep = [w for w in rows if w["windows"]]
        if not keep:
            return "none: no window was found in any room of the walk", []
        parts = [f"{room_words(w)} ({len(w['windows'])} {plural('window', len(w['windows']))}: "
                 + "; ".join(window_words(x) for x in w["windows"]) + ")" for w in keep]
        return ", ".join(parts), [{"room": w["name"], "walk": w["walk"], "windows": [x["id"] for x in w["windows"]]}
                                  for w in keep]
    keep = [w for w in rows if not w["windows"]]
    if not keep:
        return "none: every room has a window", []
    sure = [w for w in keep if w["unseen_outline"] < UNSEEN_OUTLINE_SHARE]
    unsure = [w for w in keep if w["unseen_outline"] >= UNSEEN_OUTLINE_SHARE]
    parts = []
    if sure:
        parts.append(", ".join(room_words(w) for w in sure) + f"; no window in {'it' if len(sure) == 1 else 'them'}")
    parts += [f"no window seen in {room_words(w)} ({w['unseen_outline']:.0%} of its outline was never seen)"
              for w in unsure]
    return "; ".join(parts), [{"room": w["name"], "walk": w["walk"], "seen": w["unseen_outline"] < UNSEEN_OUTLINE_SHARE}
                              for w in keep]


def asks_windows(a, nps: list[NP]) -> bool:
    """Whether the only kind asked for is the window (a structure label of sg3d/queries/vocabulary.py)."""
    if len(nps) != 1:
        return False
    r = a.ev.resolved(nps[0])
    return r.kind == "structure" and r.labels == ["window"]
