"""The layouts of each kind: which furniture stands where and what lies on it (seeded)."""
from __future__ import annotations

from typing import Callable

import numpy as np

from benchmarks.synth import scene
from benchmarks.synth.scene import Room, Thing

SMALL_COLOURS = ("red", "green", "blue", "yellow", "white", "black", "orange", "purple", "pink", "grey")
FURNITURE_COLOURS = ("brown", "white", "grey", "black", "blue", "green")
GAP = 0.05              # free space between small things (so each is its own object)


class Namer:
    def __init__(self):
        self.n = 0

    def __call__(self) -> str:
        self.n += 1
        return f"G{self.n:02d}"


def _rects_clear(rect, taken, gap) -> bool:
    x0, y0, x1, y1 = rect
    return all(x1 + gap <= a or b + gap <= x0 or y1 + gap <= c or d + gap <= y0 for a, c, b, d in taken)


def scatter(room: Room, support: Thing, area, z: float, categories, rng, new_id, taken=None) -> list[Thing]:
    """Small things of `categories` placed at random, apart, inside `area` (x0, y0, x1, y1) at height z."""
    taken = [] if taken is None else taken
    out = []
    for cat in sorted(categories, key=lambda c: -np.prod(scene.footprint(c))):    # the big ones first
        w, d = scene.footprint(cat)
        for _ in range(2000):
            x = rng.uniform(area[0] + w / 2, area[2] - w / 2) if area[2] - area[0] > w else None
            y = rng.uniform(area[1] + d / 2, area[3] - d / 2) if area[3] - area[1] > d else None
            if x is None or y is None:
                break
            rect = (x - w / 2, y - d / 2, x + w / 2, y + d / 2)
            if _rects_clear(rect, taken, GAP):
                taken.append(rect)
                colour = str(rng.choice(SMALL_COLOURS))
                out.append(scene.small(new_id(), str(cat), x, y, z, colour, support.id, rng))
                break
    room.things.extend(out)
    return out


def _room(kind: str, seed: int, rng, W=None, D=None) -> Room:
    W = W or round(float(rng.uniform(3.6, 5.2)), 2)
    D = D or round(float(rng.uniform(3.2, 4.4)), 2)
    d0 = float(rng.uniform(0.4, W - 1.4))
    w0 = float(rng.uniform(0.5, D - 1.7))
    room = Room(kind, seed, (W, D), door=(d0, d0 + scene.DOOR[0]), window=(w0, w0 + scene.WINDOW[0]))
    scene.structure(room)
    return room


def _desk_along_north(room: Room, rng, new_id, x0=None) -> Thing:
    W, D = room.size
    w, d = float(rng.uniform(1.2, 1.6)), float(rng.uniform(0.65, 0.8))
    x0 = float(rng.uniform(0.3, W - w - 0.3)) if x0 is None else x0
    t = scene.desk(new_id(), x0, D - d - 0.02, x0 + w, D - 0.02, float(rng.uniform(0.72, 0.76)),
                   str(rng.choice(FURNITURE_COLOURS)))
    room.things.append(t)
    return t


def _desk_things(room: Room, desk: Thing, rng, new_id) -> None:
    lo, hi = desk.box()
    cats = ["keyboard", "phone", "papers", "cup", "bottle", "book", "box"]
    cats += list(rng.choice(["cup", "book", "box", "bottle", "phone"], size=int(rng.integers(0, 3))))
    scatter(room, desk, (lo[0] + 0.05, lo[1] + 0.05, hi[0] - 0.05, hi[1] - 0.05), float(hi[2]), cats, rng, new_id)


def layout_desk(seed: int) -> Room:
    """A desk against the north wall with a keyboard, a phone, papers, cups, bottles, books and
    boxes on it, and a chair in front of it (the camera scans the top only)."""
    rng = np.random.default_rng(seed)
    new_id = Namer()
    room = _room("desk", seed, rng)
    d = _desk_along_north(room, rng, new_id)
    _desk_things(room, d, rng, new_id)
    lo, hi = d.box()
    room.things.append(scene.chair(new_id(), float((lo[0] + hi[0]) / 2), float(lo[1] - 0.15), 1, "black"))
    room.focus = d.id
    return room


def _furnish(room: Room, rng, new_id) -> None:
    """A desk with things and a chair on the north wall, a table with things in the middle, a
    couch or a bed on the west wall, a shelf with books on the east wall, a counter on the south."""
    W, D = room.size
    d = _desk_along_north(room, rng, new_id, x0=float(rng.uniform(0.9, max(0.95, W - 2.0))))
    _desk_things(room, d, rng, new_id)
    lo, hi = d.box()
    room.things.append(scene.chair(new_id(), float(lo[0] + 0.4), float(lo[1] - 0.3), 1, str(rng.choice(FURNITURE_COLOURS))))
    tw, td = float(rng.uniform(0.8, 1.2)), float(rng.uniform(0.6, 0.8))
    cx, cy = W / 2 + float(rng.uniform(-0.3, 0.3)), D / 2 - 0.2 + float(rng.uniform(-0.2, 0.2))
    table = scene.desk(new_id(), cx - tw / 2, cy - td / 2, cx + tw / 2, cy + td / 2, 0.74,
                       str(rng.choice(FURNITURE_COLOURS)), "dining table", "dining table")
    room.things.append(table)
    scatter(room, table, (cx - tw / 2 + 0.05, cy - td / 2 + 0.05, cx + tw / 2 - 0.05, cy + td / 2 - 0.05), 0.74,
            ["cup", "bottle", "book", "box", "papers"][: int(rng.integers(2, 6))], rng, new_id)
    room.things.append(scene.chair(new_id(), cx, cy - td / 2 - 0.3, 1, str(rng.choice(FURNITURE_COLOURS))))
    if rng.random() < 0.5:
        room.things.append(scene.couch(new_id(), 0.05, 0.6, 0.95, 2.4, str(rng.choice(FURNITURE_COLOURS))))
    else:
        room.things.append(scene.bed(new_id(), 0.05, 0.5, 1.45, 2.5, str(rng.choice(FURNITURE_COLOURS))))
    _shelf_with_things(room, rng, new_id, along="east")
    if room.door[0] > 1.6:
        c = scene.counter(new_id(), 0.3, 0.05, min(room.door[0] - 0.2, 1.9), 0.65, str(rng.choice(FURNITURE_COLOURS)))
        room.things.append(c)
        lo, hi = c.box()
        scatter(room, c, (lo[0] + 0.05, lo[1] + 0.05, hi[0] - 0.05, hi[1] - 0.05), 0.9, ["bottle", "cup", "box"], rng, new_id)


def _shelf_with_things(room: Room, rng, new_id, along: str) -> Thing:
    W, D = room.size
    boards = [0.05, 0.45, 0.85, 1.25, 1.65][: int(rng.integers(4, 6))]
    w, dep = float(rng.uniform(0.9, 1.3)), 0.35
    if along == "east":           # against the east wall, clear of its window
        y0 = 0.3 if room.window[0] > w + 0.4 else room.window[1] + 0.1
        y0 = min(y0, D - w - 0.1)
        s = scene.shelf(new_id(), W - dep - 0.02, y0, W - 0.02, y0 + w, boards, str(rng.choice(FURNITURE_COLOURS)))
        s.parts[2] = scene.box(W - 0.04, y0, 0, W - 0.02, y0 + w, boards[-1])        # its back on the wall
        area = lambda b: (W - dep + 0.02, y0 + 0.04, W - 0.06, y0 + w - 0.04)      # noqa: E731
    else:                         # against the north wall, centred
        x0 = W / 2 - w / 2
        s = scene.shelf(new_id(), x0, D - dep - 0.02, x0 + w, D - 0.02, boards, str(rng.choice(FURNITURE_COLOURS)))
        area = lambda b: (x0 + 0.04, D - dep + 0.0, x0 + w - 0.04, D - 0.06)       # noqa: E731
    room.things.append(s)
    for b in boards[1:]:
        cats = list(rng.choice(["standing book", "box", "cup", "bottle", "book"], size=int(rng.integers(2, 4))))
        scatter(room, s, area(b), b, cats, rng, new_id)
    return s


def layout_room(seed: int) -> Room:
    """A furnished room for the walk at 1.2-1.7 m."""
    rng = np.random.default_rng(seed)
    new_id = Namer()
    room = _room("room", seed, rng, W=round(float(rng.uniform(4.2, 5.2)), 2), D=round(float(rng.uniform(3.8, 4.4)), 2))
    _furnish(room, rng, new_id)
    room.focus = next(t.id for t in room.things if t.category == "desk")
    return room


def layout_robot(seed: int) -> Room:
    """A furnished room with boxes and books lying on the floor (the robot's view)."""
    room = layout_room(seed)
    room.kind = "robot"
    rng = np.random.default_rng(seed + 1000)
    new_id = Namer()
    new_id.n = len(room.things)
    W, D = room.size
    taken = [(lo[0], lo[1], hi[0], hi[1]) for lo, hi in (t.box() for t in room.objects())]
    scatter(room, room.things[0], (1.2, 1.0, W - 1.2, D - 1.6), 0.0, ["box", "box", "book"], rng, new_id, taken)
    return room


def layout_shelf(seed: int) -> Room:
    """A bookcase on the north wall full of books, boxes, cups and bottles (the shelf sweep)."""
    rng = np.random.default_rng(seed)
    new_id = Namer()
    room = _room("shelf", seed, rng)
    s = _shelf_with_things(room, rng, new_id, along="north")
    room.focus = s.id
    return room


def layout_corner(seed: int) -> Room:
    """The north-west corner: a couch on the west wall, a table with things and a chair, a desk."""
    rng = np.random.default_rng(seed)
    new_id = Namer()
    room = _room("corner", seed, rng)
    W, D = room.size
    room.things.append(scene.couch(new_id(), 0.05, D - 2.1, 0.95, D - 0.3, str(rng.choice(FURNITURE_COLOURS))))
    table = scene.desk(new_id(), 1.4, D - 1.6, 2.2, D - 1.0, 0.5, str(rng.choice(FURNITURE_COLOURS)), "dining table",
                       "dining table")
    room.things.append(table)
    room.focus = table.id
    scatter(room, table, (1.45, D - 1.55, 2.15, D - 1.05), 0.5, ["cup", "book", "bottle", "phone"], rng, new_id)
    room.things.append(scene.chair(new_id(), 2.6, D - 1.3, -1, str(rng.choice(FURNITURE_COLOURS))))
    d = _desk_along_north(room, rng, new_id, x0=1.2)
    scatter(room, d, tuple(np.r_[d.box()[0][:2] + 0.05, d.box()[1][:2] - 0.05]), float(d.box()[1][2]),
            ["box", "cup", "keyboard"], rng, new_id)
    return room


LAYOUTS: dict[str, Callable[[int], Room]] = {
    "room": layout_room, "desk": layout_desk, "robot": layout_robot, "shelf": layout_shelf, "corner": layout_corner,
}
