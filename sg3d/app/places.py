"""Rooms from one walk (`sg3d build --rooms auto`): the recording's floor map segmented into rooms
and doorways (`sg3d.ingest.places`), every object of the built room put in exactly one of them,
and the layer written to the store (`sg3d.graphdb.places`)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from sg3d.app.errors import AppError, NotFound
from sg3d.core.stored import Row
from sg3d.graphdb.protocol import GraphStore

if TYPE_CHECKING:
    from sg3d.graphdb.merge import Fence
    from numpy.typing import ArrayLike
    from sg3d.ingest.readers.frames import Frames

MAX_FRAMES = 300          # frames of the recording the floor map reads (evenly spread)
# A live map (`sg3d map --rooms auto`) finds the rooms of the frames so far at most every
# ROOMS_EVERY_S from LIVE_FRAMES of them (about 1 s of reading on 2 cores), and its last publish
# from the whole recording as a build does.
LIVE_FRAMES = 60
ROOMS_EVERY_S = 2.0
# A room found again keeps its id and name when its last middle lies within this of it.
KEEP_REACH_M = 1.0
POINTS_PER_FRAME = 5000   # about this many depth pixels of each (the stride follows the size)
# Rule "a kind is guessed from what a room holds": the labels that say each kind. A guess with its
# evidence (the labels found), never a fact; no evidence, no guess.
KIND_EVIDENCE = (
    ("kitchen", frozenset({"refrigerator", "sink", "oven", "microwave", "toaster"})),
    ("bedroom", frozenset({"bed"})),
    ("living room", frozenset({"couch", "tv"})),
    ("office", frozenset({"desk", "monitor", "keyboard", "laptop", "mouse"})),
    ("bathroom", frozenset({"toilet"})),
)


def guess_kind(labels: list[str]) -> tuple[Optional[str], list[str]]:
    """(kind, evidence): the kind of KIND_EVIDENCE with the most of its labels among `labels`
    (ties: the first listed), and those labels; (None, []) when none says anything."""
    best: tuple[Optional[str], list[str]] = (None, [])
    for kind, says in KIND_EVIDENCE:
        found = sorted(label for label in labels if label in says)
        if len(found) > len(best[1]):
            best = (kind, found)
    return best


def walk_settings(settings, rooms: Optional[str]):
    """The pipeline settings (`sg3d.ingest.pipeline.Settings`) of a build or map that finds the
    rooms of its walk (`rooms` "auto"): its discovery finds the windows too (which rooms have
    one); any other keeps `settings` and pays nothing for them."""
    from dataclasses import replace

    return replace(settings, discover=replace(settings.discover, windows=True)) if rooms == "auto" else settings


def walk_frames(seq: Frames, start: int, stop: int, most: int = MAX_FRAMES) -> list:
    """At most `most` posed frames of [start, stop), evenly spread (a frame that cannot be read, or
    has no pose yet, is left out)."""
    from sg3d.ingest.readers.frames import FrameError

    frames = []
    for i in np.unique(np.linspace(start, stop - 1, min(stop - start, most)).round().astype(int)):
        try:
            frame = seq.frame(int(i))
        except FrameError:
            continue
        if getattr(frame, "pose", None) is not None:
            frames.append(frame)
    return frames


def find_places(seq: Frames, start: int, stop: int, up: ArrayLike, floor: Optional[float], most: int = MAX_FRAMES):
    """The places layer (`sg3d.ingest.places.Places`) of frames [start, stop) and the gravity
    basis; None when the recording never saw the floor (no floor map without one)."""
    from sg3d.core.geometry import horizontal_frame
    from sg3d.ingest.places import rooms_of_walk, walk_points

    if floor is None or stop <= start:
        return None, None
    basis = horizontal_frame(up)
    frames = walk_frames(seq, start, stop, most)
    if not frames:
        return None, None
    h, w = frames[0].depth.shape
    stride = max(2, int(round(float(np.sqrt(h * w / POINTS_PER_FRAME)))))
    points, cameras = walk_points(frames, basis, float(floor), stride=stride)
    return rooms_of_walk(points, cameras), basis


def kept_names(places, basis: np.ndarray, before: list[Row]) -> dict[int, tuple[str, str]]:
    """Rule "a room keeps its id and name across publishes": each room found now (its label) ->
    (id, name) of the room written before whose middle lies in it (`room_at` within
    KEEP_REACH_M); of several, the one numbered first (rooms that merged), the others are gone.
    A room found now that holds no earlier middle is new (no entry)."""
    from sg3d.ingest.places import room_at

    if not before:
        return {}
    middles = np.array([[r["x"], r["y"], r["z"]] for r in before], float)
    at = room_at(places, (middles @ basis.T)[:, :2], reach_m=KEEP_REACH_M)
    kept: dict[int, tuple[str, str]] = {}
    for r, k in sorted(zip(before, at), key=lambda rk: _number(rk[0]["id"])):
        if int(k) > 0 and int(k) not in kept:
            kept[int(k)] = (r["id"], r["name"])
    return kept


def _number(rid: str) -> int:
    tail = rid.rsplit("#", 1)[-1]
    return int(tail) if tail.isdigit() else 0


def _ids(rid: str, places, kept: Optional[dict[int, tuple[str, str]]]) -> dict[int, tuple[str, str]]:
    """(id, name) of each room found: kept ones as they were, the others "room k" numbered on
    after every kept one (a build: "room 1..n" in the segmentation's order)."""
    if kept is None:
        return {p.label: (f"{rid}#{p.label}", f"room {p.label}") for p in places.rooms}
    out = dict(kept)
    taken = {_number(i) for i, _ in kept.values()}
    names = {n for _, n in kept.values()}
    k = max(taken, default=0)
    for p in places.rooms:
        if p.label in out:
            continue
        k += 1
        while f"room {k}" in names:
            k += 1
        out[p.label] = (f"{rid}#{k}", f"room {k}")
    return out


def layer_rows(rid: str, places, basis: np.ndarray, floor: float, objects: list[Row],
               kept: Optional[dict[int, tuple[str, str]]] = None) -> tuple[list, list, list]:
    """The rows `sg3d.graphdb.places.write_places` writes: rooms "room 1..n" (or, with `kept`,
    the ids and names they had, `kept_names`; footprint and middle in world coordinates, a guessed
    kind, the floors and walls that bound it, `structure_of`), doorways, and each object in the
    room at its position (`room_at`, no reach limit: every object in exactly one room)."""
    from sg3d.ingest.places import room_at

    def world(ab) -> list[float]:
        ab = np.asarray(ab, float).reshape(-1, 2)
        return [round(float(v), 4) for v in (np.c_[ab, np.full(len(ab), floor)] @ basis).ravel()]

    pos = np.array([[o["x"], o["y"], o["z"]] for o in objects], float).reshape(-1, 3)
    at = room_at(places, (pos @ basis.T)[:, :2], reach_m=float("inf")) if len(objects) else np.zeros(0, int)
    named = _ids(rid, places, kept)
    ids = {label: i for label, (i, _) in named.items()}
    pairs = [{"object": o["id"], "room": ids[int(k)]} for o, k in zip(objects, at) if int(k) in ids]
    structure = structure_of(places, basis, objects)
    rooms = []
    for p in places.rooms:
        kind, evidence = guess_kind([o["label"] for o, k in zip(objects, at) if int(k) == p.label])
        x, y, z = world(p.centre)
        rooms.append({"id": ids[p.label], "name": named[p.label][1], "polygon": world(p.polygon), "area": p.area_m2,
                      "free_area": p.free_m2, "x": x, "y": y, "z": z, "kind_guess": kind, "kind_evidence": evidence,
                      "unseen_outline": p.unseen_outline, "structure": structure.get(p.label, [])})
    doorways = []
    for k, d in enumerate(places.doorways, start=1):
        x, y, z = world(d.position)
        doorways.append({"id": f"{rid}#doorway {k}", "a": ids[d.a], "b": ids[d.b], "x": x, "y": y, "z": z,
                         "width": d.width_m})
    return rooms, doorways, pairs


def structure_of(places, basis: np.ndarray, objects: list[Row]) -> dict[int, list[str]]:
    """Each found room's label -> the ids of the floors and walls that bound it
    (`sg3d.ingest.places.rooms_bounded`, from each one's gravity-frame box: its middle and size)."""
    from sg3d.ingest.places import rooms_bounded

    out: dict[int, list[str]] = {}
    for o in objects:
        if o.get("layer") != "structure" or o["label"] not in ("floor", "wall") or not o.get("size"):
            continue
        middle = basis @ np.array([o["x"], o["y"], o["z"]], float)
        half = np.asarray(o["size"], float) / 2
        for k in rooms_bounded(places, middle - half, middle + half):
            out.setdefault(k, []).append(o["id"])
    return out


@dataclass(frozen=True)
class Walk:
    """The frames a walk's rooms are found from: `seq`'s [start, stop) (at most `most` of them,
    `walk_frames`), with the recording's gravity `up` and floor height."""
    seq: Any
    start: int
    stop: int
    up: Any
    floor: Optional[float]
    most: int = MAX_FRAMES


def write_walk_rooms(store: GraphStore, rid: str, walk: Walk, keep: bool = False,
                     fence: Optional[Fence] = None) -> dict:
    """Find the rooms of `walk` and write them under recorded room `rid`, in one transaction that
    `fence` (the writer's lease, `sg3d.graphdb.lease.RoomLease.fence`) checks first; `keep`: the
    rooms found again keep the ids and names written before (`kept_names`: a live map's
    publishes). What the build summary says: rooms (name, area, objects, kind guess), doorways,
    objects placed."""
    from sg3d.graphdb.places import read_places, write_places

    floor = walk.floor
    places, basis = find_places(walk.seq, walk.start, walk.stop, walk.up, floor, walk.most)
    if places is None or floor is None or not places.rooms:
        return {"rooms": [], "doorways": 0, "objects_placed": 0,
                "why": "the recording never saw the floor" if floor is None else "no free floor was seen"}
    objects = store.read("places_objects", room=rid)
    kept = kept_names(places, basis, read_places(store, rid)) if keep else None
    rooms, doorways, pairs = layer_rows(rid, places, basis, float(floor), objects, kept)
    write_places(store, rid, rooms, doorways, pairs, fence=fence)
    held = {r["id"]: 0 for r in rooms}
    for p in pairs:
        held[p["room"]] += 1
    return {"rooms": [{"name": r["name"], "area": r["area"], "objects": held[r["id"]], "kind_guess": r["kind_guess"]}
                      for r in rooms],
            "doorways": len(doorways), "objects_placed": len(pairs)}


def rename_walk_room(store: GraphStore, building: str, old: str, new: str, room: Optional[str] = None) -> dict:
    """Give the room found in a walk (`sg3d build --rooms auto`) called `old` in `building` the
    name `new` (`sg3d rooms rename`); `room`: the recording it was found in, needed only when two
    recordings of the building each found a room called `old`. AppError for a name that cannot
    name a room (`bounds.name_problem`) or is taken in the building, NotFound when no such room;
    returns {room: the recording's id, id, old, new}."""
    from sg3d.app.bounds import name_problem
    from sg3d.graphdb.places import rename_place

    problem = name_problem(new, "the new name")
    if problem:
        raise AppError(problem)
    rows = store.read("places_building_rooms", building=building.lower())
    hits = [r for r in rows if r["name"] == old and (room is None or r["walk_name"] == room)]
    if not hits:
        said = f" of recording {room!r}" if room else ""
        known = ", ".join(sorted({r["name"] for r in rows})) or "none: build with --rooms auto"
        raise NotFound(f"no room {old!r}{said} found in a walk of building {building!r} (rooms: {known})")
    if len(hits) > 1:
        raise AppError(f"{len(hits)} recordings of building {building!r} found a room {old!r} "
                       f"({', '.join(sorted(h['walk_name'] for h in hits))}): give --room RECORDING")
    hit = hits[0]
    if new != old and any(r["name"] == new for r in rows):
        raise AppError(f"building {building!r} already has a room called {new!r}")
    rename_place(store, hit["walk"], hit["id"], new)
    return {"room": hit["walk"], "id": hit["id"], "old": old, "new": new}
