"""Apartments: 2-6 rooms behind one front door, walked through in one recording.

Layouts (seeded), in the room frame (z up, floor top at z = 0), walls WALL_T thick centred on
the grid lines, each room's inside a rectangle between its walls' faces:
- 2 rooms: side by side, one doorway in the wall between them (a door, or a wide opening: an
  open-plan pair);
- 3-6 rooms: a corridor CORRIDOR_M wide running the apartment's length with rooms on both sides;
  each room's door opens onto the corridor, and two neighbours on one side may share a wide
  opening as well (open plan: a doorway the walk does not go through, seen from the rooms only).
Doors are half open (a leaf at 45 degrees into the room) or fully open (no leaf). Windows
(`_windows`, from a stream of their own so the layout of a seed is the same with or without
them) are holes in the outside walls, one or two in some rooms, none in at least one. Furniture
stands along the walls, clear of every doorway's swing, so a person can walk to each room's
middle. The walk (`walk`) starts in the first room, looks round in each room's middle, and goes
from room to room through the doors and along the corridor at 1.2-1.7 m, looking ahead and down.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from benchmarks.synth import scene
from benchmarks.synth.layouts import FURNITURE_COLOURS, Namer, scatter
from benchmarks.synth.scene import ROOM_HEIGHT, WALL_T, Room, Thing, box

CORRIDOR_M = (1.3, 1.5)          # corridor width range
ROOM_M = (3.0, 4.2)              # a room's width and depth range
DOOR_M = (0.8, 0.95)             # a door's clear width range
OPENING_M = (1.5, 1.9)           # an open-plan opening's width range
DOOR_TOP = scene.DOOR[1]
OPENING_TOP = 2.3
CORNER_CLEAR = 0.35              # a doorway keeps this far from a room's corners
SWING_M = 1.1                    # furniture keeps this far from a doorway, into the room
KINDS = ("kitchen", "living room", "bedroom", "office")
STEP_M = 0.22                    # the walk's step between frames when dense
LOOK_FRAMES = 24                 # frames of the look round in a room's middle (15 degrees apart)
TURN_STEP = np.radians(12)       # the walking gaze turns at most this much per frame
WINDOW_M = (0.8, 1.4)            # a window's width range
# A sill's height range (its top: scene.WINDOW's). Low sills: the walk looks down at the floor
# 2.2 m ahead and sees the walls only up to about 1.1 m; a look round at window height changed
# the floor map's rooms (seeds 0 and 1 of bench_walk lost a room).
SILL_M = (0.5, 0.7)
WINDOW_TOP = scene.WINDOW[2]
WINDOW_SEED = 65537              # the windows' own random stream: seed + this


@dataclass
class Space:
    """One room of an apartment: its inside rectangle (x0, y0, x1, y1) between its walls' faces."""
    id: str
    kind: str
    rect: tuple[float, float, float, float]

    @property
    def centre(self) -> np.ndarray:
        x0, y0, x1, y1 = self.rect
        return np.array([(x0 + x1) / 2, (y0 + y1) / 2])

    def polygon(self) -> list[list[float]]:
        x0, y0, x1, y1 = self.rect
        return [[round(x, 4), round(y, 4)] for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]

    def contains(self, x: float, y: float) -> bool:
        x0, y0, x1, y1 = self.rect
        return x0 <= x <= x1 and y0 <= y <= y1


@dataclass
class Doorway:
    """A gap in the wall on grid line `axis` = `at` (axis "y": a wall along x at y = at) between
    rooms a and b, from `lo` to `hi` along the wall; b lies on the line's greater side."""
    id: str
    a: str
    b: str
    axis: str
    at: float
    lo: float
    hi: float
    kind: str = "door"               # door | opening
    leaf: Optional[str] = None       # "half open" (a leaf at 45 degrees into room b) or None

    @property
    def centre(self) -> np.ndarray:
        m = (self.lo + self.hi) / 2
        return np.array([m, self.at]) if self.axis == "y" else np.array([self.at, m])

    @property
    def width(self) -> float:
        return self.hi - self.lo

    def into(self, side: int, depth: float) -> np.ndarray:
        """The point `depth` m from the doorway's centre into room b (side +1) or a (side -1)."""
        n = np.array([0.0, 1.0]) if self.axis == "y" else np.array([1.0, 0.0])
        return self.centre + side * depth * n


@dataclass
class Window:
    """A hole in room `room`'s outside wall `wall` (south y = 0, north y = D, west x = 0, east
    x = L): on grid line `axis` = `at`, from `lo` to `hi` along it, from `sill` to `top` high."""
    id: str
    room: str
    wall: str
    axis: str
    at: float
    lo: float
    hi: float
    sill: float
    top: float

    @property
    def centre(self) -> np.ndarray:
        m = (self.lo + self.hi) / 2
        return np.array([m, self.at]) if self.axis == "y" else np.array([self.at, m])


@dataclass
class Apartment(Room):
    spaces: list[Space] = field(default_factory=list)
    doorways: list[Doorway] = field(default_factory=list)
    windows: list[Window] = field(default_factory=list)
    route: list[str] = field(default_factory=list)       # the rooms in the order the walk visits them

    def space(self, i: str) -> Space:
        return next(s for s in self.spaces if s.id == i)


def _grid(rng, n: int) -> tuple[list[Space], list[tuple], float, float]:
    """The rooms' cells: (spaces, interior wall lines, length, depth). A wall line is
    (axis, at, lo, hi, room below/left, room above/right or None for a partition)."""
    size = lambda: round(float(rng.uniform(*ROOM_M)), 2)     # noqa: E731
    h = WALL_T / 2
    if n == 2:
        w1, w2, D = size(), size(), size()
        spaces = [Space("R1", "", (h, h, w1 - h, D - h)), Space("R2", "", (w1 + h, h, w1 + w2 - h, D - h))]
        return spaces, [("x", w1, 0.0, D, "R1", "R2")], w1 + w2, D
    south_n = (n - 1 + 1) // 2
    rows = [[size() for _ in range(south_n)], [size() for _ in range(n - 1 - south_n)]]
    L = max(sum(r) for r in rows)
    for r in rows:                                      # the shorter row's rooms share the rest
        extra = (L - sum(r)) / len(r)
        r[:] = [round(w + extra, 2) for w in r[:-1]] + [round(L - sum(round(w + extra, 2) for w in r[:-1]), 2)]
    ds, dn, c = size(), size(), round(float(rng.uniform(*CORRIDOR_M)), 2)
    spaces, lines = [Space("C", "corridor", (h, ds + h, L - h, ds + c - h))], []
    lines += [("y", ds, 0.0, L, None, "C"), ("y", ds + c, 0.0, L, "C", None)]
    k = 1
    for row, (y0, y1) in zip(rows, ((0.0, ds), (ds + c, ds + c + dn))):
        x = 0.0
        for j, w in enumerate(row):
            spaces.append(Space(f"R{k}", "", (x + h, y0 + h, x + w - h, y1 - h)))
            if j:
                lines.append(("x", x, y0, y1, f"R{k - 1}", f"R{k}"))
            x += w
            k += 1
    return spaces, lines, L, ds + c + dn


def _gap(rng, lo: float, hi: float, width: float) -> Optional[tuple[float, float]]:
    if hi - lo - 2 * CORNER_CLEAR < width:
        return None
    g0 = float(rng.uniform(lo + CORNER_CLEAR, hi - CORNER_CLEAR - width))
    return round(g0, 3), round(g0 + width, 3)


def _doorways(rng, spaces: list[Space], lines: list[tuple]) -> list[Doorway]:
    """A door from every room onto the corridor (or between the two rooms), and one open-plan
    opening between two neighbours on one side with probability 1/2."""
    by = {s.id: s for s in spaces}
    out: list[Doorway] = []
    partitions = [ln for ln in lines if ln[4] and ln[5]]
    if not any(s.id == "C" for s in spaces):
        axis, at, lo, hi, a, b = partitions[0]
        opening = rng.random() < 0.4
        w = float(rng.uniform(*(OPENING_M if opening else DOOR_M)))
        g = _gap(rng, lo, hi, w) or _gap(rng, lo, hi, DOOR_M[0])
        assert g is not None
        out.append(Doorway("D1", a, b, axis, at, *g, kind="opening" if opening else "door"))
    else:
        c = by["C"]
        for s in spaces:
            if s.id == "C":
                continue
            south = s.rect[3] < c.rect[1]
            g = _gap(rng, s.rect[0], s.rect[2], float(rng.uniform(*DOOR_M)))
            assert g is not None
            at = c.rect[1] - WALL_T / 2 if south else c.rect[3] + WALL_T / 2
            out.append(Doorway(f"D{len(out) + 1}", *((s.id, "C") if south else ("C", s.id)), "y", at, *g))
        if partitions and rng.random() < 0.5:
            axis, at, lo, hi, a, b = partitions[int(rng.integers(len(partitions)))]
            g = _gap(rng, lo + WALL_T, hi - WALL_T, float(rng.uniform(*OPENING_M)))
            if g is not None:
                out.append(Doorway(f"D{len(out) + 1}", a, b, axis, at, *g, kind="opening"))
    for d in out:
        if d.kind == "door" and rng.random() < 0.6:
            d.leaf = "half open"
    return out


def _wall_boxes(axis: str, at: float, lo: float, hi: float, gaps: list[Doorway],
               windows: tuple[Window, ...] = ()) -> list:
    """The boxes of one wall line with its doorways cut out (a lintel above each) and its
    windows (a piece under the sill, a lintel above the top)."""
    h = WALL_T / 2
    cuts = sorted([(d.lo, d.hi, 0.0, DOOR_TOP if d.kind == "door" else OPENING_TOP) for d in gaps]
                  + [(w.lo, w.hi, w.sill, w.top) for w in windows])
    pieces, x = [], lo - h
    for g0, g1, bottom, top in cuts:
        pieces.append((x, g0, 0.0, ROOM_HEIGHT))
        if bottom > 0:
            pieces.append((g0, g1, 0.0, bottom))
        pieces.append((g0, g1, top, ROOM_HEIGHT))
        x = g1
    pieces.append((x, hi + h, 0.0, ROOM_HEIGHT))
    if axis == "y":
        return [box(a, at - h, z0, b, at + h, z1) for a, b, z0, z1 in pieces if b > a]
    return [box(at - h, a, z0, at + h, b, z1) for a, b, z0, z1 in pieces if b > a]


def _leaf(d: Doorway) -> scene.Part:
    """A door leaf 4 cm thick hinged at the doorway's low end, turned 45 degrees into the room
    (never into the corridor)."""
    length = d.width - 0.02
    side = -1 if d.b == "C" else 1
    face = d.at + side * WALL_T / 2
    hinge = np.array([d.lo + 0.01, face]) if d.axis == "y" else np.array([face, d.lo + 0.01])
    along, normal = (np.array([1.0, 0.0]), np.array([0.0, 1.0]))[:: 1 if d.axis == "y" else -1]
    ang = float(np.arctan2(*(along + side * normal)[::-1]))
    mid = hinge + length / 2 * np.array([np.cos(ang), np.sin(ang)])
    p = box(mid[0] - length / 2, mid[1] - 0.02, 0.01, mid[0] + length / 2, mid[1] + 0.02, DOOR_TOP - 0.02)
    p.yaw = float(ang)
    return p


def _structure(apt: Apartment, lines: list[tuple], L: float, D: float) -> None:
    t = WALL_T
    add = apt.things.append
    add(Thing("floor", "floor", None, "brown", [box(-t, -t, -0.05, L + t, D + t, 0.0)], structure=True))
    add(Thing("ceiling", "ceiling", None, "white", [box(-t, -t, ROOM_HEIGHT, L + t, D + t, ROOM_HEIGHT + 0.05)],
              structure=True))
    for k, (axis, at, lo, hi) in enumerate(_outer(L, D) + [ln[:4] for ln in lines]):
        gaps = [d for d in apt.doorways if d.axis == axis and abs(d.at - at) < 1e-6 and lo <= d.lo and d.hi <= hi]
        add(Thing(f"wall-{k + 1}", "wall", None, "white", _wall_boxes(axis, at, lo, hi, gaps), structure=True))
    for d in apt.doorways:
        if d.leaf:
            add(Thing(f"door-{d.id}", "door", None, "white", [_leaf(d)], structure=True))


def _keep_out(apt: Apartment, s: Space) -> list[tuple]:
    """Rectangles in `s` where no furniture stands: each doorway's approach and swing."""
    out = []
    for d in apt.doorways:
        if s.id not in (d.a, d.b):
            continue
        side = 1 if s.id == d.b else -1
        a, b = d.lo - 0.3, d.hi + 0.3
        near, far = d.at, d.at + side * SWING_M
        lo_, hi_ = min(near, far), max(near, far)
        out.append((a, lo_, b, hi_) if d.axis == "y" else (lo_, a, hi_, b))
    return out


def _against_wall(s: Space, length: float, depth: float, taken: list[tuple], rng) -> Optional[tuple]:
    """A rectangle length x depth against one of the room's walls, clear of `taken` by 0.1 m."""
    x0, y0, x1, y1 = s.rect
    for _ in range(200):
        side = int(rng.integers(4))
        if side < 2:
            if x1 - x0 < length + 0.1:
                continue
            a = float(rng.uniform(x0 + 0.05, x1 - 0.05 - length))
            r = (a, y0 + 0.02, a + length, y0 + 0.02 + depth) if side == 0 else (a, y1 - 0.02 - depth, a + length, y1 - 0.02)
        else:
            if y1 - y0 < length + 0.1:
                continue
            a = float(rng.uniform(y0 + 0.05, y1 - 0.05 - length))
            r = (x0 + 0.02, a, x0 + 0.02 + depth, a + length) if side == 2 else (x1 - 0.02 - depth, a, x1 - 0.02, a + length)
        if all(r[2] + 0.1 <= t[0] or t[2] + 0.1 <= r[0] or r[3] + 0.1 <= t[1] or t[3] + 0.1 <= r[1] for t in taken):
            taken.append(r)
            return r
    return None


def _colour(rng) -> str:
    return str(rng.choice(FURNITURE_COLOURS))


def _top_things(apt: Apartment, t: Thing, cats: list[str], rng, new_id) -> None:
    lo, hi = t.box()
    scatter(apt, t, (lo[0] + 0.05, lo[1] + 0.05, hi[0] - 0.05, hi[1] - 0.05), float(t.tops[0]), cats, rng, new_id)


def _furnish(apt: Apartment, s: Space, rng, new_id) -> None:
    """Furniture by the room's kind, each piece against a wall: a kitchen's counter, fridge and
    table; a living room's couch and a cabinet with a TV; a bedroom's bed and cabinet; an
    office's desk with a chair."""
    taken = _keep_out(apt, s)

    def place(length, depth):
        r = _against_wall(s, length, depth, taken, rng)
        return None if r is None else tuple(round(v, 3) for v in r)

    def add(t: Thing, cats=()):
        apt.things.append(t)
        if cats:
            _top_things(apt, t, list(cats), rng, new_id)

    plan = {"kitchen": [("counter", 1.8, 0.6), ("refrigerator", 0.7, 0.7), ("dining table", 1.1, 0.8)],
            "living room": [("couch", 2.0, 0.9), ("cabinet", 1.2, 0.45)],
            "bedroom": [("bed", 2.0, 1.4), ("cabinet", 1.0, 0.45)],
            "office": [("desk", 1.4, 0.7), ("cabinet", 0.9, 0.4)]}[s.kind]
    for cat, length, depth in plan:
        r = place(length, depth)
        if r is None:
            continue
        x0, y0, x1, y1 = r
        if cat == "counter":
            add(scene.counter(new_id(), x0, y0, x1, y1, _colour(rng)), ["bottle", "cup", "box"])
        elif cat == "refrigerator":
            add(Thing(new_id(), "refrigerator", "refrigerator", "white", [box(x0, y0, 0, x1, y1, 1.8)], tops=[1.8]))
        elif cat in ("dining table", "desk"):
            coco = "dining table" if cat == "dining table" else None
            add(scene.desk(new_id(), x0, y0, x1, y1, 0.74, _colour(rng), cat, coco),
                ["cup", "book", "bottle"] if cat == "dining table" else ["keyboard", "cup", "book"])
        elif cat == "couch":
            add(scene.couch(new_id(), x0, y0, x1, y1, _colour(rng)))
        elif cat == "bed":
            add(scene.bed(new_id(), x0, y0, x1, y1, _colour(rng)))
        else:
            cab = Thing(new_id(), "cabinet", None, _colour(rng), [box(x0, y0, 0, x1, y1, 0.8)], tops=[0.8])
            add(cab, ["tv" if s.kind == "living room" else "book", "box"])


def layout_apartment(seed: int, windows: bool = True) -> Apartment:
    """2-6 rooms (module docstring), furnished by kind, with the walk's route; `windows`: cut
    into the outside walls (`_windows`; else the walls are whole)."""
    rng = np.random.default_rng(seed)
    new_id = Namer()
    n = int(rng.integers(2, 7))
    spaces, lines, L, D = _grid(rng, n)
    kinds = list(rng.permutation(KINDS))
    for k, s in enumerate(x for x in spaces if x.id != "C"):
        s.kind = str(kinds[k % len(kinds)])
    apt = Apartment("apartment", seed, (L, D), spaces=spaces)
    apt.doorways = _doorways(rng, spaces, lines)
    _structure(apt, lines, L, D)
    for s in spaces:
        if s.id != "C":
            _furnish(apt, s, rng, new_id)
    doors = {d.b if d.a == "C" else d.a: d for d in apt.doorways if "C" in (d.a, d.b)}
    apt.route = sorted(doors, key=lambda r: doors[r].centre[0]) if doors else [s.id for s in spaces]
    apt.windows = _windows(apt, np.random.default_rng(seed + WINDOW_SEED), L, D) if windows else []
    for k, (axis, at, lo, hi) in enumerate(_outer(L, D)):
        wall = apt.by_id(f"wall-{k + 1}")
        gaps = [d for d in apt.doorways if d.axis == axis and abs(d.at - at) < 1e-6]
        wall.parts = _wall_boxes(axis, at, lo, hi, gaps, tuple(w for w in apt.windows if w.axis == axis and w.at == at))
    return apt


def _outer(L: float, D: float) -> list[tuple[str, float, float, float]]:
    """The outside wall lines (axis, at, lo, hi): south, north, west, east."""
    return [("y", 0.0, 0.0, L), ("y", D, 0.0, L), ("x", 0.0, 0.0, D), ("x", L, 0.0, D)]


def _outside_sides(s: Space, L: float, D: float) -> list[tuple[str, str, float, float, float]]:
    """The room's sides on the outside walls: (name, axis, at, lo, hi) with lo, hi its inside."""
    x0, y0, x1, y1 = s.rect
    h = WALL_T / 2 + 1e-6
    sides = [("south", "y", 0.0, x0, x1, y0 <= h), ("north", "y", D, x0, x1, y1 >= D - h),
             ("west", "x", 0.0, y0, y1, x0 <= h), ("east", "x", L, y0, y1, x1 >= L - h)]
    return [(n, a, at, lo, hi) for n, a, at, lo, hi, ok in sides if ok]


def _in_front(apt: Apartment, s: Space, axis: str, at: float, lo: float, hi: float, sill: float) -> bool:
    """Whether furniture taller than the sill stands against the wall in [lo, hi] (a window
    behind a fridge is no window a walk could see)."""
    for t in apt.objects():
        a, b = t.box()
        if not s.contains(float(a[0] + b[0]) / 2, float(a[1] + b[1]) / 2) or b[2] <= sill - 0.1:
            continue
        k, j = (0, 1) if axis == "y" else (1, 0)
        near = min(abs(a[j] - at), abs(b[j] - at)) < 0.6
        if near and a[k] < hi + 0.1 and b[k] > lo - 0.1:
            return True
    return False


def _windows(apt: Apartment, rng, L: float, D: float) -> list[Window]:
    """Windows in the rooms' outside walls: each room (not the corridor) gets 0, 1 or 2 (WINDOW_M
    wide, SILL_M up to WINDOW_TOP), the first of them at least 1, clear of the room's corners and
    doorways and of furniture standing in front; one room with outside walls keeps none."""
    rooms = [s for s in apt.spaces if s.id != "C" and _outside_sides(s, L, D)]
    bare = str(rng.choice([s.id for s in rooms])) if rooms else None
    out: list[Window] = []
    for s in rooms:
        want = 0 if s.id == bare else max(int(rng.choice([0, 1, 1, 2])), int(not out))
        sides = _outside_sides(s, L, D)
        for _ in range(want * 10):
            if sum(w.room == s.id for w in out) >= want:
                break
            name, axis, at, lo, hi = sides[int(rng.integers(len(sides)))]
            width, sill = float(rng.uniform(*WINDOW_M)), round(float(rng.uniform(*SILL_M)), 2)
            if hi - lo - 2 * CORNER_CLEAR < width:
                continue
            g0 = round(float(rng.uniform(lo + CORNER_CLEAR, hi - CORNER_CLEAR - width)), 3)
            g1 = round(g0 + width, 3)
            clash = any(w.axis == axis and w.at == at and g0 < w.hi + 0.3 and w.lo - 0.3 < g1 for w in out) or any(
                d.axis == axis and abs(d.at - at) < 1e-6 and g0 < d.hi + 0.3 and d.lo - 0.3 < g1 for d in apt.doorways)
            if not clash and not _in_front(apt, s, axis, at, g0, g1, sill):
                out.append(Window(f"W{len(out) + 1}", s.id, name, axis, at, g0, g1, sill, WINDOW_TOP))
    return out


def _door_to(apt: Apartment, a: str, b: str) -> Doorway:
    """The doorway between rooms a and b, a door before an opening."""
    return min((d for d in apt.doorways if {d.a, d.b} == {a, b}), key=lambda d: d.kind != "door")


def _legs(apt: Apartment) -> list[tuple[str, np.ndarray]]:
    """The route as ("look", centre) and ("go", point) steps."""
    steps: list[tuple[str, np.ndarray]] = []
    corridor = any(s.id == "C" for s in apt.spaces)
    for k, rid in enumerate(apt.route):
        s = apt.space(rid)
        if k:
            prev = apt.route[k - 1]
            if corridor:
                for r, leaving in ((prev, True), (rid, False)):
                    d = _door_to(apt, r, "C")
                    side_room = 1 if d.b == r else -1
                    middle = abs(float(apt.space("C").centre[1]) - d.at)
                    pts = [d.into(side_room, 0.8), d.centre, d.into(-side_room, middle)]
                    steps += [("go", p) for p in (pts if leaving else pts[::-1])]
            else:
                d = _door_to(apt, prev, rid)
                side = 1 if d.b == rid else -1
                steps += [("go", d.into(-side, 0.8)), ("go", d.centre), ("go", d.into(side, 0.8))]
        steps += [("go", s.centre), ("look", s.centre)]
    return steps


def _turn_toward(gaze: float, want: float, limit: float) -> float:
    d = (want - gaze + np.pi) % (2 * np.pi) - np.pi
    return gaze + float(np.clip(d, -limit, limit))


def walk(apt: Room, n: int, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """The walk through the route at 1.2-1.7 m: STEP_M steps between points, looking ahead (the
    gaze turns at most TURN_STEP per frame, swaying a little) and down; in each room's middle a
    look round of LOOK_FRAMES views. `n` is ignored: the walk's own steps keep a camera's speed
    and turn rate (`sg3d.ingest.readers.pose_check`) at 30 frames/s, so every pose is kept."""
    assert isinstance(apt, Apartment)
    out: list[tuple[np.ndarray, np.ndarray]] = []
    here: Optional[np.ndarray] = None
    phase = float(rng.uniform(0, 2 * np.pi))
    gaze = phase
    height = lambda: 1.45 + 0.25 * np.sin(phase + 0.23 * len(out))      # noqa: E731
    for what, p in _legs(apt):
        if what == "look":
            for i in range(LOOK_FRAMES):
                a = gaze + 2 * np.pi * (i + 1) / LOOK_FRAMES
                u = np.array([np.cos(a), np.sin(a)])
                out.append((np.r_[p + 0.1 * u, height()], np.r_[p + 2.2 * u, 0.0]))
            continue
        if here is None:
            here = p
            continue
        seg = p - here
        steps = max(1, int(np.ceil(float(np.linalg.norm(seg)) / STEP_M)))
        want = float(np.arctan2(seg[1], seg[0]))
        for j in range(1, steps + 1):
            gaze = _turn_toward(gaze, want, TURN_STEP)
            a = gaze + 0.12 * np.sin(phase + 0.3 * len(out))
            e = here + seg * j / steps
            out.append((np.r_[e, height()], np.r_[e + 2.2 * np.array([np.cos(a), np.sin(a)]), 0.3]))
        here = p
    return out


def room_of(apt: Apartment, x: float, y: float) -> Optional[str]:
    return next((s.id for s in apt.spaces if s.contains(x, y)), None)


def doorway_seen(scene_, apt: Apartment, poses: list[np.ndarray], K: np.ndarray, w: int, h: int) -> dict[str, int]:
    """Frames that see each doorway's middle at 1 m height: inside the image, in front, and no
    surface nearer than it along the ray."""
    import open3d as o3d

    out = {}
    for d in apt.doorways:
        target = np.r_[d.centre, 1.0]
        n = 0
        for pose in poses:
            cam = np.linalg.inv(pose) @ np.r_[target, 1.0]
            if cam[2] <= 0.1:
                continue
            u, v = K[0, 0] * cam[0] / cam[2] + K[0, 2], K[1, 1] * cam[1] / cam[2] + K[1, 2]
            if not (0 <= u < w and 0 <= v < h):
                continue
            ray = np.r_[pose[:3, 3], target - pose[:3, 3]].astype(np.float32)[None]
            t = float(scene_.scene.cast_rays(o3d.core.Tensor.from_numpy(ray))["t_hit"].numpy()[0])
            n += bool(t > 0.97)
        out[d.id] = n
    return out


def truth(apt: Apartment, poses: list[np.ndarray], scene_, K, w: int, h: int, to_world: np.ndarray) -> dict:
    """The apartment's ground truth: every room's footprint (polygon and area, room frame and
    world), every doorway (rooms, position, width, kind, leaf, frames that saw it, whether the
    walk went through it), every window (room, wall, middle, width, sill, top; each room lists
    its windows' ids) and the room of every object."""
    seen = doorway_seen(scene_, apt, poses, K, w, h)
    walked = set()
    for a, b in zip(apt.route, apt.route[1:]):
        walked |= {_door_to(apt, a, "C").id, _door_to(apt, b, "C").id} if any(s.id == "C" for s in apt.spaces) \
            else {_door_to(apt, a, b).id}
    R, t = to_world[:3, :3], to_world[:3, 3]

    def world(xy, z=0.0):
        return [round(float(v), 4) for v in R @ np.r_[xy, z] + t]

    windows = [{"id": w.id, "room": w.room, "wall": w.wall, "position": [round(float(v), 4) for v in w.centre],
                "position_world": world(w.centre, (w.sill + w.top) / 2), "width": round(w.hi - w.lo, 3),
                "sill": w.sill, "top": w.top} for w in apt.windows]
    rooms = [{"id": s.id, "kind": s.kind, "polygon": s.polygon(), "polygon_world": [world(p) for p in s.polygon()],
              "area": round((s.rect[2] - s.rect[0]) * (s.rect[3] - s.rect[1]), 3),
              "windows": [w["id"] for w in windows if w["room"] == s.id]} for s in apt.spaces]
    doorways = [{"id": d.id, "rooms": [d.a, d.b], "position": [round(float(v), 4) for v in d.centre],
                 "position_world": world(d.centre), "width": round(d.width, 3), "kind": d.kind, "leaf": d.leaf,
                 "frames_seen": seen[d.id], "walked_through": d.id in walked} for d in apt.doorways]
    objects = {}
    for o in apt.objects():
        lo, hi = o.box()
        objects[o.id] = room_of(apt, float(lo[0] + hi[0]) / 2, float(lo[1] + hi[1]) / 2)
    return {"rooms": rooms, "doorways": doorways, "windows": windows, "object_rooms": objects, "route": list(apt.route)}
