"""What re-scans changed in a room: objects moved, added and removed (`sg3d changes`, ask's
"what changed in the kitchen", "what is gone", "where was the cup before").

Scans are recorded by the merge (sg3d.merge.rescan, sg3d.graphdb.rescan); this composes the room's scans and the objects
they touched. The window is the scans after `since` (a scan id), by default the room's last scan.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Optional, cast

from sg3d.app.errors import AppError, NotFound
from sg3d.core.stored import Row
from sg3d.graphdb.protocol import GraphStore

if TYPE_CHECKING:
    from sg3d.queries.answer.parts import AnswerObject
    from sg3d.queries.logic import ChangeQuery


def _scans(store: GraphStore, rid: str) -> list[Row]:
    return store.read("scan_list", room=rid)


def _window(scans: list[Row], since: Optional[str], every: bool = False) -> list[str]:
    ids = [s["id"] for s in scans]
    if every:
        return ids
    if since is None:
        return ids[-1:]
    if since not in ids:
        raise AppError(f"no scan {since!r} in this room (its scans: {', '.join(ids) or 'none'})")
    return ids[ids.index(since) + 1:]


def _point(o: dict, x, y, z) -> dict:
    return {"id": o["id"], "name": o.get("name") or o["label"], "label": o["label"],
            "x": round(float(x), 3), "y": round(float(y), 3), "z": round(float(z), 3)}


def room_changes(store: GraphStore, room: str, building: str = "default", since: Optional[str] = None,
                 every_scan: bool = False) -> dict:
    """{room, scans, since, moved, added, removed}: the objects the scans after `since` (default:
    the last scan alone; `every_scan`: all of them) moved (with `from`: where they were before the
    first of those moves), added (first seen then and still there) and removed. Each object: id,
    name, label, x, y, z."""
    from sg3d.graphdb.values import room_id
    from sg3d.queries.naming import names_in_store

    rid = room_id(building, room)
    scans = _scans(store, rid)
    if not scans:
        if not store.read("eval_room_exists", room=rid):
            raise NotFound(f"no room {room!r} in building {building!r}")
        raise NotFound(f"room {room!r} has no recorded scans (build it with `sg3d build`)")
    window = _window(scans, since, every_scan)
    rows = store.read("changes_objects", room=rid, scans=window) if window else []
    names = names_in_store(store.read, rows)
    moved, added, removed = [], [], []
    for o in rows:
        o["name"] = names.get(o["id"], o["label"])
        if o.get("removed_scan") in window:
            removed.append(_point(o, o["x"], o["y"], o["z"]))
            continue
        moves = [k for k, s in enumerate(o.get("history_scans") or []) if s in window]
        if moves:
            k = moves[0]
            moved.append({**_point(o, o["x"], o["y"], o["z"]),
                          "from": {"x": round(float(o["history_x"][k]), 3), "y": round(float(o["history_y"][k]), 3),
                                   "z": round(float(o["history_z"][k]), 3)}})
        elif o.get("first_scan") in window and o.get("removed_at") is None:
            added.append(_point(o, o["x"], o["y"], o["z"]))
    return {"room": rid, "scans": window, "since": since, "moved": moved, "added": added, "removed": removed}


def places_before(store: GraphStore, labels: Optional[list[str]], room: Optional[str] = None, building: Optional[str] = None) -> list[Row]:
    """Where objects of these labels were before they moved or went: per object its name, label,
    where it is now (None if removed) and its earlier places, oldest first."""
    from sg3d.queries.naming import names_in_store

    rows = store.read("history_objects", labels=labels, room=room, building=building)
    names = names_in_store(store.read, rows)
    out = []
    for o in rows:
        before = [{"scan": s, "x": round(float(x), 3), "y": round(float(y), 3), "z": round(float(z), 3)}
                  for s, x, y, z in zip(o.get("history_scans") or [], o.get("history_x") or [],
                                        o.get("history_y") or [], o.get("history_z") or [])]
        gone = o.get("removed_at") is not None
        if gone:
            before.append({"scan": o.get("removed_scan"), "x": round(float(o["x"]), 3),
                           "y": round(float(o["y"]), 3), "z": round(float(o["z"]), 3)})
        out.append({"id": o["id"], "name": names.get(o["id"], o["label"]), "label": o["label"], "room": o["room"],
                    "now": None if gone else {"x": round(float(o["x"]), 3), "y": round(float(o["y"]), 3),
                                              "z": round(float(o["z"]), 3)},
                    "before": before})
    return out


def _where(p: dict) -> str:
    return f"({p['x']:.2f}, {p['y']:.2f}, {p['z']:.2f})"


def _room_ids(store: GraphStore, name: Optional[str], building: Optional[str]) -> list[str]:
    if name:
        b = building.lower() if building else None
        spellings = sorted({name, name.lower(), name.title(), name.capitalize(), name.upper()})
        rows = store.read("vqa_room_named", names=spellings, building=b) or \
            store.read("vqa_rooms", room=name.lower(), building=b)
        return [r["id"] for r in rows]
    return [r["room"] for r in store.read("scan_rooms")
            if building is None or r["room"].split("/", 1)[0] == building]


def change_answer(store: GraphStore, question: str, cq: ChangeQuery, room: Optional[str] = None,
                  building: Optional[str] = None):
    """The answer (sg3d.queries.vqa.Answer) to a question about re-scans ("what changed in the kitchen",
    "what is gone", "where was the cup before"), as the question reader read it (`cq`)."""
    from sg3d.queries.vqa import Answer

    if cq.room and room and cq.room.lower() != room.lower():
        return Answer(question, False, f"the question says '{cq.room}' but --room is '{room}'", form="changes")
    rids = _room_ids(store, cq.room or room, building)
    if not rids:
        where = f"room '{cq.room or room}'" if (cq.room or room) else "any room"
        return Answer(question, False, f"no scans recorded for {where}", form="changes")
    if cq.form == "before" and cq.target is not None:     # "before" always names its objects
        rows = [r for r in places_before(store, cq.target.labels, building=building) if r["room"] in rids]
        if not rows:
            return Answer(question, True, f"no {cq.target.describe()} has moved or gone", "history", [], [])
        parts = []
        for r in rows:
            before = ", then ".join(_where(p) for p in r["before"])
            now = f"now at {_where(r['now'])}" if r["now"] else "now gone"
            parts.append(f"the {r['name']} was at {before}; {now}")
        return Answer(question, True, "; ".join(parts), "history", rows, cast("list[AnswerObject]", rows))
    value: dict[str, list[Any]] = {"moved": [], "added": [], "removed": []}
    for rid in rids:
        b, name = rid.split("/", 1)
        if cq.form == "gone":
            value["removed"] += room_changes(store, name, b, every_scan=True)["removed"]
        else:
            got = room_changes(store, name, b)
            for k in value:
                value[k] += got[k]
    if cq.form == "gone":
        text = ("gone: " + ", ".join(f"the {o['name']} (was at {_where(o)})" for o in value["removed"])
                if value["removed"] else "nothing is gone")
        return Answer(question, True, text, "changes", value["removed"], value["removed"])
    parts = [f"moved: the {o['name']} from {_where(o['from'])} to {_where(o)}" for o in value["moved"]]
    parts += [f"appeared: the {o['name']} at {_where(o)}" for o in value["added"]]
    parts += [f"gone: the {o['name']} (was at {_where(o)})" for o in value["removed"]]
    objects = value["moved"] + value["added"] + value["removed"]
    return Answer(question, True, "; ".join(parts) if parts else "nothing changed at the last scan", "changes",
                  value, objects)
