"""One function per operation of a logical form: its answer text, value and the rows it rests on.

"How tall" is the box height along up; "how high" is the box top above the top of the room's
floor node, and the box height is said beside it where the two differ (a tv on a shelf). No object of an asked kind in scope: "I have not found ...", never "there is no".
"""
from __future__ import annotations

from typing import Optional, Sequence

from sg3d.core.stored import Row
from sg3d.core.model import UNNAMED_LABEL
from sg3d.core.relation_rules import SYMMETRIC
from sg3d.queries import walk
from sg3d.queries.lexicon import lemma
from sg3d.queries.logic import NP, Filter, Form
from sg3d.queries.sets import Evaluator, Unanswerable, activity, same_as_roots
from sg3d.queries.vocabulary import (
    ABSENT,
    ACTIVITIES,
    DISTANCE_SUPERLATIVES,
    EXTRA_AFFORDANCES,
    GERUNDS,
    LIST_SHOWN,
    SUPERLATIVES,
)
from sg3d.queries.answer.wording import plural, the, without_place


def _join(items: list[str]) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


class Answerer:
    """What every operation needs: the evaluated sets, names, and how to say a set in words."""

    def __init__(self, ev: Evaluator, room_label: Optional[str]):
        self.ev, self.scene, self.run = ev, ev.scene, ev.run
        self.where = f" in the {room_label}" if room_label else ""
        self.thumbnail: Optional[bytes] = None

    def names(self, rows: list[Row]) -> dict[str, str]:
        return self.run.names(rows)

    def listing(self, rows: list[Row]) -> str:
        from sg3d.queries.naming import describe_unnamed

        named = self.names(rows[:LIST_SHOWN])
        parts = []
        for o in sorted(rows[:LIST_SHOWN], key=lambda o: named[o["id"]]):
            name = the(named[o["id"]])
            if o["label"] == UNNAMED_LABEL and describe_unnamed(o):
                name = f"{name} ({describe_unnamed(o)})"
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
        return self.ev.resolved(np).noun(n) + (f" for {GERUNDS[activity(np.purpose)]}" if np.purpose else "")

    def phrase(self, np: NP, n: int, filters: Sequence[Filter] = ()) -> str:
        extra = [_filter_text(self, f) for f in list(np.filters) + list(filters)]
        return " ".join([self.noun_of(np, n)] + extra)

    def absence(self) -> Optional[str]:
        if not self.ev.absent:
            return None
        r = self.ev.absent[0]
        what = " or ".join(r.names) if r.names else r.np.text()
        article = "an" if what[:1] in "aeiou" else "a"
        return f"I have not found {article} {what}{self.where} ({ABSENT})"


def _filter_text(a: Answerer, f: Filter) -> str:
    """The filter in the answer's words: the other set as the answer phrases it ("next to a
    cup" when any cup was asked for, "next to the cup" when one was)."""
    if f.other.number:
        return f.describe(a.phrase(f.other, 1))
    if f.kind == "except" and f.other.alternatives and f.other.joined == "and":
        # "other than books and cups": every one of each kind
        return "except " + " and ".join(a.phrase(x, 2) for x in f.other.alternatives)
    if f.kind == "except" and not f.other.alternatives and f.other.words and not f.other.filters:
        r = a.ev.resolved(f.other)
        if r.kind == "any" and r.colour:       # "that is not white": every white thing
            return f"except {r.colour} things"
        if lemma(f.other.words[-1]) != f.other.words[-1]:      # "that are not cups": every cup
            return f"except {a.phrase(f.other, 2)}"
    article = "a" if f.other.indefinite and not f.other.alternatives else "the"
    if article == "a" and a.phrase(f.other, 1)[:1] in "aeiou":
        article = "an"
    return f.describe(f"{article} {a.phrase(f.other, 1)}")


def _sizes(o: dict) -> str:
    s = o.get("size") or []
    return " x ".join(f"{float(v):.2f}" for v in s) + " m" if s else "unknown"


def row_value(o: dict, name: str) -> dict:
    out = {k: o.get(k) for k in ("id", "label", "colour", "colour2", "layer", "shape", "volume", "size", "room")
           if o.get(k) is not None}
    out["name"] = name
    return out


def _head(form: Form) -> NP:
    return form.sets[0] if form.sets else NP([])


def _all_rows(ev: Evaluator, form: Form, np: NP) -> list[Row]:
    rows = ev.members(np)
    for f in form.filters:
        rows = ev.apply(f, rows)
    return rows


def op_count(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    extra = extra_views(a, rows)
    n = len(rows) - extra
    text = f"{n} {a.phrase(np, n, form.filters)}{a.where}"
    labels: dict[str, int] = {}
    for o in rows:
        labels[o["label"]] = labels.get(o["label"], 0) + 1
    if len(labels) > 1 and not extra:
        text += " (" + ", ".join(f"{v} {'unnamed ' if k == UNNAMED_LABEL else ''}{plural(k, v)}"
                                 for k, v in sorted(labels.items(), key=lambda kv: (-kv[1], kv[0]))) + ")"
    if extra:
        text += f" [{extra} seen from two rooms counted once]"
    if n == 0 and a.absence():
        text = f"0: {a.absence()}"
    return text, n, rows


def extra_views(a: Answerer, rows: list[Row]) -> int:
    """How many of `rows` are further views of one physical object stored in two rooms (linked
    by SAME_AS): each connected group of them counts once. Only across rooms."""
    if len({o["room"] for o in rows}) < 2 or not a.run.read("vqa_same_as_count")[0]["n"]:
        return 0
    roots = same_as_roots(a.run.read("vqa_same_as", labels=None, rooms=a.scene.rooms, colour=None),
                          keep={o["id"] for o in rows})
    return sum(1 for x, root in roots.items() if root != x)


def op_exists(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    n = len(rows)
    if n and np.number is not None:         # "is chair 1 next to the table"
        named = a.names(rows)
        rest = " ".join(_filter_text(a, f) for f in list(np.filters) + list(form.filters))
        return f"yes, {named[rows[0]['id']]} is {rest}".rstrip(), True, rows
    if not n and np.number is not None and not a.absence():
        rest = " ".join(_filter_text(a, f) for f in list(np.filters) + list(form.filters))
        return f"no, {np.text()} is not {rest}".rstrip(), False, rows
    if n:
        named = a.names(rows[:LIST_SHOWN])
        text = f"yes, {n} {a.phrase(np, n, form.filters)}{a.where}: " + _join(sorted(named[o['id']] for o in rows[:LIST_SHOWN]))
    else:
        text = a.absence() or f"no: I have not found {_what_not_found(a, np, form)}{a.where} ({ABSENT})"
    return text, n > 0, rows


def _what_not_found(a: "Answerer", np: NP, form: Form) -> str:
    """"a cup on the table", or "anything next to the sink" when no kind was asked."""
    if np.words and a.ev.resolved(np).kind != "any" or np.alternatives:
        what = a.phrase(np, 1, form.filters)
        return f"{'an' if what[:1] in 'aeiou' else 'a'} {what}"
    r = a.ev.resolved(np) if np.words else None
    said = [x for x in ((r.size, r.shape, r.colour) if r is not None else ()) if x]     # "anything purple"
    said += [_filter_text(a, f) for f in list(np.filters) + list(form.filters)]
    return " ".join(["anything"] + said)


def op_at_least(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    n, k = len(rows), form.number or 0
    holds = n > k if form.compare == "more" else n == k if form.compare == "exactly" else n < k
    if n == 0 and a.absence():      # "is there no fridge": none found, said as not found
        return f"{'yes' if holds else 'no'}: {a.absence()}", holds, rows
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
        on_top = on_unnamed_top(a, np, form)
        if on_top is not None:
            return on_top
        return (a.absence() or f"nothing found: I have not found {_what_not_found(a, np, form)}{a.where} "
                               f"({ABSENT})"), [], rows
    named = a.names(rows)
    return f"{n} {what}{a.where}: {a.listing(rows)}", [row_value(o, named[o["id"]]) for o in rows], rows


def on_unnamed_top(a: Answerer, np: NP, form: Form) -> Optional[tuple[str, list, list[Row]]]:
    """"What is on the desk?" where no desk or table is named in scope: what stands ON an unnamed
    object that could be its top (`unnamed.could_be_top`: a desk scanned from above), said as
    unnamed (`unnamed.on_unnamed_top`); the value stays empty, as for any absence. None when the
    question is not "what is on <a worktop>" or no such top is stored."""
    from sg3d.queries import unnamed

    if not a.ev.absent or np.words or np.alternatives:
        return None
    r = a.ev.absent[0]
    on = [f for f in list(np.filters) + list(form.filters)
          if f.kind == "rel" and f.relation == "on" and not f.negated and not f.reverse and f.other is r.np]
    if not on or not set(r.labels or []) & unnamed.WORKTOPS:
        return None
    tops = unnamed.tops(a.run, a.scene.rooms)
    if not tops:
        return None
    top = tops[0]
    linked = a.run.read("vqa_scene_linked", ids=[top["id"]], types=["ON"], rooms=a.scene.rooms or [top["room"]])
    things = sorted((o for o in linked if not o["outgoing"]), key=lambda o: o["id"])
    if not things:
        return None
    what = " or ".join(r.names) if r.names else r.np.text()
    return unnamed.on_unnamed_top(what, a.where, top, a.listing(things)), [], things


def op_where(a: Answerer, form: Form):
    from sg3d.queries import viewpoint as views

    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    if not rows:
        return (a.absence() or f"I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"), [], rows
    shown = rows[:LIST_SHOWN]
    ids = {o["id"] for o in shown}
    places: dict[str, list[Row]] = {i: [] for i in ids}
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
        name = the(without_place(named[o["id"]], said))
        parts.append(f"{name} is " + (f"{said}, in the {room}" if said else f"in the {room}"))
    more = f"; ... {len(rows) - len(shown)} more" if len(rows) > len(shown) else ""
    value = [{**row_value(o, named[o["id"]]), "relations": [{"rel": p["rel"], "other_id": p["other_id"],
                                                          "other_label": p["other_label"]} for p in places[o["id"]]]}
             for o in shown]
    return "; ".join(parts) + more, value, rows


def op_attribute(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    if not rows:
        return (a.absence() or f"I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"), None, rows
    named = a.names(rows[:LIST_SHOWN])
    values, parts = [], []
    for o in rows[:LIST_SHOWN]:
        v, said = _attribute_of(a, o, form.attribute or "size")
        values.append(v)
        parts.append(f"{the(named[o['id']])} {said}")
    text = "; ".join(parts)
    if len(rows) > LIST_SHOWN:
        text += f"; ... {len(rows) - LIST_SHOWN} more"
    return text, values[0] if len(values) == 1 else values, rows


# "how high": an object whose top is this close to its box height stands on the floor
HIGH_SAME_M = 0.05


def _attribute_of(a: Answerer, o: dict, attribute: str):
    size = [float(v) for v in (o.get("size") or [0, 0, 0])]
    if attribute == "colour":
        c2 = f" with {o['colour2']}" if o.get("colour2") else ""
        return o.get("colour"), f"is {o.get('colour') or 'of unknown colour'}{c2}"
    if attribute == "size":
        return size, f"is {_sizes(o)} (w x d x h)"
    if attribute == "tall":
        return round(size[2], 3), f"is {size[2]:.2f} m tall (its box height)"
    if attribute in ("width", "length", "depth"):
        # width and length: the larger horizontal extent of the box (a cabinet 1.15 m wide and
        # 0.56 m deep); depth: the smaller one
        v = min(size[0], size[1]) if attribute == "depth" else max(size[0], size[1])
        word = {"length": "long", "width": "wide", "depth": "deep"}[attribute]
        return round(v, 3), f"is {v:.2f} m {word} (the {'smaller' if attribute == 'depth' else 'larger'} " \
                            f"horizontal side of its box)"
    # high: the box top above the floor
    floor = a.scene.floor_level(o["room"])
    if floor is None:
        return None, (f"has a box {size[2]:.2f} m tall, but I have not found the floor of the "
                      f"{(o.get('room') or '').split('/', 1)[-1]}, so its height above it is unknown")
    h = a.scene.top(o) - floor
    if abs(h - size[2]) <= HIGH_SAME_M:         # it stands on the floor: one number says both
        return round(h, 3), f"is {h:.2f} m high (its top above the floor; its box is {size[2]:.2f} m tall)"
    # "how high is the tv" may ask how far up it reaches or how tall it is: both are said
    return round(h, 3), f"reaches {h:.2f} m above the floor (top of its box); it is {size[2]:.2f} m tall itself"


def op_extreme(a: Answerer, form: Form):
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    if not rows:
        return (a.absence() or f"I have not found {a.phrase(np, 1, form.filters)}{a.where} ({ABSENT})"), None, rows
    o = rows[0]
    name = the(a.names([o])[o["id"]])
    k = a.ev.key(np)(o)
    if np.superlative in DISTANCE_SUPERLATIVES:
        detail = f"{k:.2f} m from the {a.phrase(np.toward, 1) if np.toward is not None else '?'}"
    else:
        key = SUPERLATIVES[np.superlative or ""][0]
        detail = {"volume": f"{k:.3g} m^3", "height": f"{k:.2f} m tall", "top": f"top at {k:.2f} m"}[key]
    what = a.noun_of(np, 1)
    filters = " ".join(_filter_text(a, f) for f in np.filters)
    thumb = a.run.read("vqa_thumbnail", id=o["id"])
    a.thumbnail = thumb[0]["thumbnail"] if thumb else None
    return (f"the {np.superlative} {what}{' ' + filters if filters else ''}{a.where}: {name} ({detail})",
            row_value(o, name), rows)


def op_distance(a: Answerer, form: Form):
    if len(form.sets) == 1 and not form.sets[0].alternatives:
        return _apart(a, form.sets[0])            # "how far apart are the two cups"
    if len(form.sets) == 1 and len(form.sets[0].alternatives) == 2:
        x, y = form.sets[0].alternatives          # "how far apart are tv 1 and tv 2"
    elif len(form.sets) == 2:
        x, y = form.sets
    else:
        raise Unanswerable("a distance is between two things; ask e.g. 'how far is the cup from the sink'")
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


def _apart(a: Answerer, np: NP):
    """How far apart the objects of one set are: the one distance of two, else the closest
    pair, said as such."""
    rows = a.ev.members(np)
    if len(rows) < 2:
        return (a.absence() or f"I have found {len(rows)} {a.phrase(np, len(rows))}{a.where}, not two "
                               f"({ABSENT})"), None, rows
    pairs = [(a.scene.distance(p, q), p, q) for i, p in enumerate(rows) for q in rows[i + 1:]]
    d, p, q = min(pairs, key=lambda t: (t[0], t[1]["id"], t[2]["id"]))
    named = a.names([p, q])
    text = f"{the(named[p['id']])} and {the(named[q['id']])} are {d:.2f} m apart (box centre to box centre)"
    if len(pairs) > 1:
        text += f"; the closest of {len(pairs)} pairs of {len(rows)} {a.phrase(np, len(rows))}"
    return text, round(d, 3), [p, q]


def _measure(a: Answerer, o: dict, key: str) -> float:
    if key == "height":
        return float((o.get("size") or [0, 0, 0])[2])
    if key == "width":          # wider / longer: the box's larger horizontal side
        size = o.get("size") or [0, 0, 0]
        return max(float(size[0]), float(size[1]))
    return a.scene.top(o) if key == "top" else float(o.get("volume") or 0.0)


def op_size_compare(a: Answerer, form: Form):
    """"is the cup bigger than the book" (box volumes; "higher": box tops), and "which is
    bigger, the cup or the book". A set of several objects is represented by its largest
    (its highest) one, and the answer says so."""
    key = form.attribute or "volume"
    sets = []
    for np in form.sets[:2]:
        rows = _all_rows(a.ev, form, np)
        if not rows:
            return (a.absence() or f"I have not found {a.phrase(np, 1)}{a.where} ({ABSENT})"), None, []
        sets.append((np, rows, max(rows, key=lambda o: (_measure(a, o, key), o["id"]))))
    (x, rx, ox), (y, ry, oy) = sets
    vx, vy = _measure(a, ox, key), _measure(a, oy, key)
    named = a.names([ox, oy])
    unit = {"volume": "m^3", "top": "m (box top)", "height": "m tall", "width": "m wide"}[key]
    most = {"volume": "largest", "top": "highest", "height": "tallest", "width": "widest"}[key]
    said = [f"{the(named[o['id']])} {v:.3g} {unit}" + (f" (the {most} of "
                                                       f"{len(r)})" if len(r) > 1 else "")
            for o, v, r in ((ox, vx, rx), (oy, vy, ry))]
    detail = f"{said[0]}, {said[1]}"
    if form.op == "size_which":
        word = {("volume", "more"): "bigger", ("volume", "fewer"): "smaller", ("top", "more"): "higher",
                ("top", "fewer"): "lower", ("height", "more"): "taller",
                ("height", "fewer"): "shorter", ("width", "more"): "wider",
                ("width", "fewer"): "narrower"}[(key, form.compare or "more")]
        win = ox if (vx >= vy) == (form.compare != "fewer") else oy
        if vx == vy:
            return f"neither: they are the same ({detail})", None, [ox, oy]
        return f"{the(named[win['id']])} is {word} ({detail})", named[win["id"]], [ox, oy]
    holds = vx > vy if form.compare != "fewer" else vx < vy
    return f"{'yes' if holds else 'no'}: {detail}", holds, [ox, oy]


def op_rooms_counted(a: Answerer, form: Form):
    """"in how many rooms is there a chair": the rooms holding one, counted and named."""
    text, value, rows = op_rooms(a, form)
    if not value:
        return text, 0, rows
    n = len(value)
    return f"{n} room{'s' if n != 1 else ''}: {text}", n, rows


def op_rooms(a: Answerer, form: Form):
    if form.number is not None:
        return _rooms_by_count(a, form)
    if form.lacking or form.sets and form.sets[0].alternatives and form.sets[0].joined == "and":
        return _rooms_holding_all(a, form)
    if walk.asks_windows(a, form.sets) and walk.walk_layer(a):
        return walk.op_walk_windows(a, lacking=False)
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    per: dict[str, int] = {}
    for o in rows:
        per[o["room"]] = per.get(o["room"], 0) + 1
    if not per:
        return (a.absence() or f"none: no room holds {a.phrase(np, 1, form.filters)}"), [], rows
    text = ", ".join(f"{rid.split('/', 1)[-1]} ({k} {a.phrase(np, k)})" for rid, k in sorted(per.items()))
    return text, [{"room": r, "n": k} for r, k in sorted(per.items())], rows


def _rooms_by_count(a: Answerer, form: Form):
    """"which rooms have more than two chairs" (fewer than, exactly): every room in scope whose
    count of the kind holds the condition; a room holding none counts 0."""
    rooms = {r["id"]: r for r in a.run.read("vqa_rooms_all", building=a.ev.building)}
    if a.scene.rooms is not None:
        rooms = {k: v for k, v in rooms.items() if k in a.scene.rooms}
    np = _head(form)
    rows = _all_rows(a.ev, form, np)
    per = {rid: 0 for rid in rooms}
    for o in rows:
        per[o["room"]] = per.get(o["room"], 0) + 1
    k = form.number or 0
    keep = sorted(rid for rid, n in per.items()
                  if (n > k if form.compare == "more" else n == k if form.compare == "exactly" else n < k))
    said = {"more": "more than", "fewer": "fewer than", "exactly": "exactly"}[form.compare or "more"]
    if not keep:
        return f"none: no room has {said} {k:g} {a.phrase(np, 2)}", [], []
    text = ", ".join(f"{rid.split('/', 1)[-1]} ({per[rid]} {a.phrase(np, per[rid])})" for rid in keep)
    return text, [{"room": rid, "n": per[rid]} for rid in keep], [o for o in rows if o["room"] in keep]


def _an(noun: str) -> str:
    """The noun with its indefinite article: "a tv", "an oven"."""
    return f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun}"


def _rooms_holding_all(a: Answerer, form: Form):
    """"which rooms have a chair and a tv" (every kind said with "and"), "which rooms have no
    fridge", "which rooms have a chair but no fridge": the rooms in scope holding each wanted kind
    and none of the lacking ones; only those rooms are named."""
    wanted = [n for s in form.sets for n in (s.alternatives if s.joined == "and" and s.alternatives else [s])]
    layer = walk.walk_layer(a) if form.lacking else []
    if layer:           # a walk split into rooms: those rooms, not the recording
        return walk.op_walk_rooms_lacking(a, wanted, form.lacking, layer)
    rooms = {r["id"]: r for r in a.run.read("vqa_rooms_all", building=a.ev.building)}
    if a.scene.rooms is not None:
        rooms = {k: v for k, v in rooms.items() if k in a.scene.rooms}
    per: dict[str, dict[int, int]] = {rid: {} for rid in rooms}
    rows: list[Row] = []
    for i, np in enumerate(wanted):
        found = _all_rows(a.ev, form, np)
        rows += found
        for o in found:
            if o["room"] in per:
                per[o["room"]][i] = per[o["room"]].get(i, 0) + 1
    held = {o["room"] for np in form.lacking for o in _all_rows(a.ev, form, np)}
    keep = sorted(rid for rid in rooms if len(per[rid]) == len(wanted) and rid not in held)
    lacking = " or ".join(a.phrase(np, 1) for np in form.lacking)
    if not keep:
        have = " and ".join(_an(a.phrase(np, 1)) for np in wanted)
        why = (f"no room has {have} without {_an(lacking)}" if wanted else f"every room has {_an(lacking)}") \
            if form.lacking else f"no room has {have}"
        return f"none: {why}", [], rows
    def said(rid: str) -> str:
        counts = ", ".join(f"{per[rid][i]} {a.phrase(np, per[rid][i])}" for i, np in enumerate(wanted))
        return rid.split("/", 1)[-1] + (f" ({counts})" if counts else "")
    text = ", ".join(said(rid) for rid in keep)
    if form.lacking:
        text += f"; no {lacking} in {'it' if len(keep) == 1 else 'them'}"
    return text, [{"room": rid, "n": sum(per[rid].values())} for rid in keep], [o for o in rows if o["room"] in keep]


NEIGHBOUR_WORDS = ("neighbour", "neighbor", "neighbouring room", "neighboring room", "adjacent room")


def op_room_most(a: Answerer, form: Form):
    """"which room has the most chairs", "which 2 rooms have the fewest objects", "which room has
    the fewest neighbours" (rooms linked by ADJACENT_TO: a scan saw into both)."""
    np = _head(form)
    rooms = {r["id"]: r for r in a.run.read("vqa_rooms_all", building=a.ev.building)}
    if a.scene.rooms is not None:
        rooms = {k: v for k, v in rooms.items() if k in a.scene.rooms}
    if form.among:      # "which room has more chairs, the kitchen or the study": only those
        named: set[str] = set()
        for np_room in form.among:
            r = a.ev.resolved(np_room, may_be_room=True)
            if r.kind != "room":
                raise Unanswerable(f"'{np_room.text()}' is not a room in the store")
            named |= set(r.room_ids)
        rooms = {k: v for k, v in rooms.items() if k in named}
    per = {rid: 0 for rid in rooms}
    neighbours = " ".join(lemma(w) for w in np.words) in NEIGHBOUR_WORDS
    if neighbours:
        rows: list[Row] = []
        for e in a.run.read("vqa_rooms_adjacent", rooms=sorted(rooms)) if rooms else []:
            if not form.among or e["room"] in per:
                per[e["room"]] = per.get(e["room"], 0) + 1
    else:
        rows = _all_rows(a.ev, form, np)
        if form.among:          # the rooms named only: another room's objects never win
            rows = [o for o in rows if o["room"] in per]
        for o in rows:
            per[o["room"]] = per.get(o["room"], 0) + 1
    if not per:
        return "the store holds no rooms", None, rows

    def said(k: int) -> str:
        return f"{k} neighbour{'s' if k != 1 else ''}" if neighbours else f"{k} {a.phrase(np, k)}"

    sign = 1 if form.compare == "more" else -1
    ranked = sorted(per.items(), key=lambda kv: (-sign * kv[1], kv[0]))
    want = int(form.number or 1)
    if want > 1:
        top = ranked[:want]
        text = ", ".join(f"the {r.split('/', 1)[-1]} ({said(k)})" for r, k in top)
        if len(per) < want:
            text += f"; only {len(per)} room{'s' if len(per) != 1 else ''} in scope"
        return text, [{"room": r, "n": k} for r, k in top], rows
    best = ranked[0]
    ties = [r for r, k in per.items() if k == best[1]]
    text = f"the {best[0].split('/', 1)[-1]} ({said(best[1])})"
    if len(ties) > 1:
        text = "a tie: " + ", ".join(f"the {r.split('/', 1)[-1]}" for r in sorted(ties)) + f" ({said(best[1])} each)"
    if len(per) == 1:
        text += "; it is the only room in scope"
    return text, {"room": best[0], "n": best[1]}, rows


def op_rooms_next_to(a: Answerer, form: Form):
    """"what rooms are next to the kitchen": the rooms of a walk a doorway joins to it (the places
    layer, sg3d/queries/walk.py) when the room is one found in a walk; else the recorded rooms
    linked by ADJACENT_TO (a scan saw into both)."""
    layer = walk.walk_layer(a)
    if layer and walk.named(layer, walk.said_name(a, _head(form)))[0]:
        return walk.op_walk_next(a, _head(form), layer, hold=False)
    r = a.ev.resolved(_head(form), may_be_room=True)
    if r.kind != "room":
        raise Unanswerable(f"'{_head(form).text()}' is not a room in the store")
    ids = r.room_ids
    rows = a.run.read("vqa_rooms_adjacent", rooms=ids)
    names = sorted({x["name"] for x in rows})
    if not names:
        return f"none: no room shares objects with the {r.room} (rooms are linked when a scan sees into both)", [], []
    return f"{_join(names)} (rooms that share objects with the {r.room})", names, []


def op_rooms_next_hold(a: Answerer, form: Form):
    """"what is in the room next to the kitchen": the rooms of a walk a doorway joins to the named
    one and what each holds."""
    layer = walk.walk_layer(a)
    if not layer:
        raise Unanswerable("no recording in scope was split into rooms (build it with --rooms auto): "
                           "I know no doorways between rooms")
    return walk.op_walk_next(a, _head(form), layer, hold=True)


def op_route(a: Answerer, form: Form):
    """"how do I get from the kitchen to the bedroom": the doorways on the way (sg3d/queries/walk.py)."""
    layer = walk.walk_layer(a)
    if not layer:
        raise Unanswerable("no recording in scope was split into rooms (build it with --rooms auto): "
                           "I know no doorways between rooms")
    return walk.op_walk_route(a, form.sets[0], form.sets[1], layer)


def op_room_count(a: Answerer, form: Form):
    """Rooms in scope; a recorded room whose walk was split into rooms (`sg3d build --rooms auto`)
    counts as the rooms found in it."""
    rows = a.run.read("vqa_rooms_all", building=a.ev.building)
    walked = {r["id"]: a.run.read("places_rooms", room=r["id"]) for r in rows}
    if any(walked.values()):
        parts = [f"{w['name']} of the {r['name']}"
                 + (f" (looks like {_an(w['kind_guess'])})" if w["kind_guess"] else "") for r in rows for w in walked[r["id"]]] + [r["name"] for r in rows if not walked[r["id"]]]
        return f"{len(parts)} rooms: " + _join(parts), len(parts), []
    names = sorted({r["name"] for r in rows})
    return f"{len(rows)} room{'s' if len(rows) != 1 else ''}: " + _join(names) if rows else "0 rooms", len(rows), []


PREPOSITION = {"sit": "on", "drink": "from", "put things down": "on", "store things": "in", "work": "at",
               "keep things cold": "in"}


def op_affordance(a: Answerer, form: Form):
    """"where can I sit", "I need something to pour water into": the objects of the curated
    activity table (vocabulary.ACTIVITIES), whichever layer holds them (a counter or a shelf
    sg3d named from its shape is furniture to put things on)."""
    verb = form.verb or ""
    extra = next((k for k in sorted(EXTRA_AFFORDANCES, key=len, reverse=True)
                  if verb.split()[:len(k.split())] == k.split()), None)
    if extra is not None:
        key, labels = extra, EXTRA_AFFORDANCES[extra]
    else:
        key = activity(verb)
        labels = ACTIVITIES[key]
    objs = [o for o in a.scene.objects.values() if o["label"] in labels]
    if form.sets:           # "which desk could I work at": of that kind only
        kind = {o["id"] for np in form.sets for o in a.ev.members(np)}
        objs = [o for o in objs if o["id"] in kind]
    for f in form.filters:
        objs = a.ev.apply(f, objs)
    objs.sort(key=lambda o: o["id"])
    asked = form.compare == "exists"       # "is there a cup I could drink from": yes or no first
    if not objs:
        return (f"{'no: ' if asked else ''}I have not found anything to {key} on or at{a.where} (looked for "
                f"{_join(labels)}; {ABSENT})"), [], []
    text = f"{'yes, ' if asked else ''}to {key}: {a.listing(objs)}{a.where} (what one can {key} " \
           f"{PREPOSITION.get(key, 'on or at')}: {', '.join(labels)})"
    return text, [o["id"] for o in objs], objs


OPS = {"count": op_count, "exists": op_exists, "at_least": op_at_least, "compare": op_compare,
       "list": op_list, "where": op_where, "attribute": op_attribute, "extreme": op_extreme,
       "distance": op_distance, "rooms": op_rooms, "room_most": op_room_most,
       "rooms_next_to": op_rooms_next_to, "room_count": op_room_count, "affordance": op_affordance,
       "rooms_counted": op_rooms_counted, "size_compare": op_size_compare, "size_which": op_size_compare,
       "rooms_next_hold": op_rooms_next_hold, "route": op_route}


