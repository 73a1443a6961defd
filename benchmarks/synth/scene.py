"""Seeded procedural rooms: every thing is a few boxes and cylinders with one albedo, placed by
rules that hold in real rooms (furniture against walls and clear of each other, small things
lying on a top or a shelf board, nothing floating).

Room frame: z up, the floor's top at z = 0, the room's inside is [0, W] x [0, D]. A thing's box
is the axis-aligned box of its parts; its support is the thing whose top it lies on ("floor" for
furniture), and the support's top equals the thing's bottom exactly.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

# name -> (albedo RGB in 0..1); the names are plain colour words a user would say
PALETTE = {
    "red": (0.78, 0.12, 0.10), "green": (0.15, 0.55, 0.20), "blue": (0.12, 0.25, 0.75),
    "yellow": (0.90, 0.80, 0.15), "white": (0.92, 0.92, 0.90), "black": (0.06, 0.06, 0.07),
    "grey": (0.50, 0.50, 0.50), "brown": (0.45, 0.28, 0.12), "orange": (0.95, 0.50, 0.10),
    "purple": (0.45, 0.15, 0.60), "pink": (0.95, 0.55, 0.70),
}
STRUCTURE_COLOURS = {"floor": (0.55, 0.45, 0.35), "wall": (0.85, 0.84, 0.80), "ceiling": (0.95, 0.95, 0.95)}
ROOM_HEIGHT = 2.6
WALL_T = 0.1
DOOR = (0.9, 2.05)                 # width, height
WINDOW = (1.2, 0.9, 2.1)           # width, sill, top


@dataclass
class Part:
    kind: str                      # box | cylinder
    lo: np.ndarray                 # box: corner; cylinder: centre of its base
    hi: np.ndarray                 # box: corner; cylinder: (radius, radius, height)
    yaw: float = 0.0               # box: turn about the vertical through its centre (radians)

    def corners(self) -> np.ndarray:
        """A box's 8 corners after its turn (`yaw`)."""
        xs, ys, zs = zip(self.lo, self.hi)
        pts = np.array([(x, y, z) for x in xs for y in ys for z in zs], float)
        if self.yaw:
            c, s = np.cos(self.yaw), np.sin(self.yaw)
            mid = (self.lo + self.hi) / 2
            rel = pts[:, :2] - mid[:2]
            pts[:, :2] = mid[:2] + rel @ np.array([[c, s], [-s, c]])
        return pts


@dataclass
class Thing:
    id: str
    category: str
    coco: Optional[str]
    colour: str
    parts: list[Part]
    support: str = "floor"
    tops: list[float] = field(default_factory=list)    # heights of the surfaces it offers
    structure: bool = False

    def box(self) -> tuple[np.ndarray, np.ndarray]:
        los, his = [], []
        for p in self.parts:
            if p.kind == "box" and p.yaw:
                los.append(p.corners().min(axis=0))
                his.append(p.corners().max(axis=0))
            elif p.kind == "box":
                los.append(p.lo)
                his.append(p.hi)
            else:
                r, h = p.hi[0], p.hi[2]
                los.append(p.lo - np.array([r, r, 0.0]))
                his.append(p.lo + np.array([r, r, h]))
        return np.min(los, axis=0), np.max(his, axis=0)

    @property
    def albedo(self) -> tuple[float, float, float]:
        return STRUCTURE_COLOURS.get(self.category) or PALETTE[self.colour]


def box(x0, y0, z0, x1, y1, z1) -> Part:
    return Part("box", np.array([x0, y0, z0], float), np.array([x1, y1, z1], float))


def cylinder(x, y, z, r, h) -> Part:
    return Part("cylinder", np.array([x, y, z], float), np.array([r, r, h], float))


@dataclass
class Room:
    kind: str
    seed: int
    size: tuple[float, float]
    things: list[Thing] = field(default_factory=list)
    door: tuple[float, float] = (0.0, 0.0)       # x range of the door in the wall y = 0
    window: tuple[float, float] = (0.0, 0.0)     # y range of the window in the wall x = W
    focus: Optional[str] = None                   # the thing the camera path is about

    def by_id(self, i: str) -> Thing:
        return next(t for t in self.things if t.id == i)

    def objects(self) -> list[Thing]:
        return [t for t in self.things if not t.structure]


def structure(room: Room) -> None:
    """Floor, ceiling and four walls; a door in the wall y = 0 and a window in the wall x = W."""
    W, D = room.size
    H, t = ROOM_HEIGHT, WALL_T
    (d0, d1), (w0, w1) = room.door, room.window
    sill, top = WINDOW[1], WINDOW[2]
    add = room.things.append
    add(Thing("floor", "floor", None, "brown", [box(-t, -t, -0.05, W + t, D + t, 0.0)], structure=True))
    add(Thing("ceiling", "ceiling", None, "white", [box(-t, -t, H, W + t, D + t, H + 0.05)], structure=True))
    add(Thing("wall-south", "wall", None, "white", [box(-t, -t, 0, d0, 0, H), box(d1, -t, 0, W + t, 0, H),
                                                     box(d0, -t, DOOR[1], d1, 0, H)], structure=True))
    add(Thing("wall-north", "wall", None, "white", [box(-t, D, 0, W + t, D + t, H)], structure=True))
    add(Thing("wall-west", "wall", None, "white", [box(-t, 0, 0, 0, D, H)], structure=True))
    add(Thing("wall-east", "wall", None, "white", [box(W, 0, 0, W + t, w0, H), box(W, w1, 0, W + t, D, H),
                                                    box(W, w0, 0, W + t, w1, sill), box(W, w0, top, W + t, w1, H)],
              structure=True))


# --- furniture: each returns a Thing whose parts stand on z = 0 inside (x0, y0)-(x1, y1) ---

def desk(i, x0, y0, x1, y1, h, colour, category="desk", coco=None) -> Thing:
    """A top 3 cm thick on four legs (a desk, a dining table)."""
    leg, parts = 0.05, [box(x0, y0, h - 0.03, x1, y1, h)]
    for x, y in ((x0, y0), (x1 - leg, y0), (x0, y1 - leg), (x1 - leg, y1 - leg)):
        parts.append(box(x, y, 0, x + leg, y + leg, h - 0.03))
    return Thing(i, category, coco, colour, parts, tops=[h])


def counter(i, x0, y0, x1, y1, colour) -> Thing:
    return Thing(i, "counter", None, colour, [box(x0, y0, 0, x1, y1, 0.9)], tops=[0.9])


def shelf(i, x0, y0, x1, y1, boards, colour) -> Thing:
    """A bookcase open on its front: two sides, a back, a board at each level of `boards`."""
    t, top = 0.02, boards[-1]
    parts = [box(x0, y0, 0, x0 + t, y1, top), box(x1 - t, y0, 0, x1, y1, top)]
    back_at_y1 = True
    parts.append(box(x0, y1 - t, 0, x1, y1, top) if back_at_y1 else box(x0, y0, 0, x1, y0 + t, top))
    for b in boards:
        parts.append(box(x0 + t, y0, b - t, x1 - t, y1 - t, b))
    return Thing(i, "shelf", None, colour, parts, tops=list(boards))


def chair(i, x, y, facing, colour) -> Thing:
    """Seat 0.45 m high on four legs, a back 0.4 m above the seat on the side away from `facing`
    (+1: the sitter faces +y, -1: faces -y)."""
    s, h, leg = 0.44, 0.45, 0.04
    x0, y0 = x - s / 2, y - s / 2
    parts = [box(x0, y0, h - 0.05, x0 + s, y0 + s, h)]
    for a, b in ((x0, y0), (x0 + s - leg, y0), (x0, y0 + s - leg), (x0 + s - leg, y0 + s - leg)):
        parts.append(box(a, b, 0, a + leg, b + leg, h - 0.05))
    by = y0 if facing > 0 else y0 + s - 0.05
    parts.append(box(x0, by, h, x0 + s, by + 0.05, h + 0.42))
    return Thing(i, "chair", "chair", colour, parts)


def couch(i, x0, y0, x1, y1, colour) -> Thing:
    """Base to 0.42 m, a back along y1, arms at both ends."""
    parts = [box(x0, y0, 0, x1, y1, 0.42), box(x0, y1 - 0.2, 0.42, x1, y1, 0.85),
             box(x0, y0, 0.42, x0 + 0.18, y1 - 0.2, 0.62), box(x1 - 0.18, y0, 0.42, x1, y1 - 0.2, 0.62)]
    return Thing(i, "couch", "couch", colour, parts)


def bed(i, x0, y0, x1, y1, colour) -> Thing:
    return Thing(i, "bed", "bed", colour, [box(x0, y0, 0, x1, y1, 0.5), box(x0, y1 - 0.06, 0.5, x1, y1, 1.0)],
                 tops=[0.5])


# --- small things: each lies with its bottom at z on its support ---

SMALL = {   # category -> (coco, (width, depth, height) or (radius, radius, height) for cylinders, shape)
    "cup": ("cup", (0.04, 0.04, 0.10), "cylinder"),
    "bottle": ("bottle", (0.035, 0.035, 0.24), "cylinder"),
    "box": (None, (0.20, 0.15, 0.12), "box"),
    "book": ("book", (0.16, 0.23, 0.035), "box"),
    "keyboard": ("keyboard", (0.45, 0.14, 0.02), "box"),
    "phone": ("cell phone", (0.075, 0.15, 0.01), "box"),
    "papers": (None, (0.21, 0.30, 0.012), "box"),
    "standing book": ("book", (0.03, 0.17, 0.24), "box"),
    "tv": ("tv", (0.75, 0.06, 0.45), "box"),
}
FLAT = ("keyboard", "phone", "papers", "book")


def small(i, category, x, y, z, colour, support, rng) -> Thing:
    """A small thing centred at (x, y) whose bottom is at z; boxes get a little size jitter."""
    coco, (a, b, c), shape = SMALL[category]
    if shape == "cylinder":
        return Thing(i, category, coco, colour, [cylinder(x, y, z, a, c)], support=support)
    if category not in ("keyboard", "phone", "papers"):
        a, b, c = (v * rng.uniform(0.85, 1.2) for v in (a, b, c))
    name = "book" if category == "standing book" else category
    return Thing(i, name, coco, colour, [box(x - a / 2, y - b / 2, z, x + a / 2, y + b / 2, z + c)], support=support,
                 tops=[z + c])


def footprint(category: str) -> tuple[float, float]:
    _, (a, b, _c), shape = SMALL[category]
    return (2 * a, 2 * b) if shape == "cylinder" else (a * 1.2, b * 1.2)
