"""Rule "shape class": what an unnamed object's box (and, where there are enough, its points) says
of its shape, in one word stored on the node (`shape`) and said in answers ("a flat black object
45x14 cm on the desk").

`shape_class(size, points, basis, centre)` decides, in this order (the first that holds):

- flat: the height is at most FLAT_MAX_M and below FLAT_RATIO of the SMALLER horizontal side.
  Things that lie flat (keyboards 2-4 cm, phones, books, closed laptops, mats, papers) are a few
  centimetres tall however wide they are; a depth box adds a centimetre or two of what they lie
  on, and 5 cm is where the things a room generator calls flat (1-5 cm) end and a shoebox (10 cm)
  begins. The ratio keeps a small cube out (a 4 x 4 x 3 cm eraser is not flat).
- panel (said "thin upright"): one horizontal side below PANEL_RATIO of the other and the height
  above that thin side: it stands on edge (a monitor without its foot, a book on a shelf, a board,
  a picture, a door leaf).
- round: a near-square footprint (the longer side at most ROUND_SQUARE times the shorter) of at
  least ROUND_MIN_M, and at least ROUND_MIN_POINTS surface points of which at least
  ROUND_RIM_SHARE show the outline (normalised radius >= ROUND_RIM) and none lies in the corners
  of their own smallest rectangle (|u| + |v| > ROUND_CORNER, with u, v the horizontal offsets
  from its centre over its half sides; the rectangle turned in ROUND_TURN_DEG steps, so a box
  standing at 45 degrees to the room's axes, whose points never reach the corners of the room-
  aligned box, still shows its own): a disc's points never reach a rectangle's corners (|u| + |v|
  <= 1.41), a box's rim does (up to 2). The surface sample is of 2.5 cm voxel centres, each up to
  1.25 cm off per axis: at a 0.2 m footprint that moves |u| + |v| by at most 0.25, still below
  1.7; below it a cup and its box cannot be told apart at that grain, so small things are never
  called round.
- tall: the height at least TALL_RATIO times the longer horizontal side (a bottle, a lamp, a
  standing roll).
- box-shaped: the three sides within BOX_RATIO of each other.
- None: no class fits (a long low bar, a 1.4 x 1.2 x 0.2 m slab): nothing is said.
"""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

FLAT_MAX_M = 0.05
# Boxes are built from 2.5 cm voxels, so a height of 5 cm comes out as 0.05000000000000002:
# heights are compared with FLAT_MAX_M give or take this much.
ROUNDING_M = 1e-6
FLAT_RATIO = 0.25
PANEL_RATIO = 0.25
ROUND_MIN_M = 0.20
ROUND_SQUARE = 1.2
ROUND_MIN_POINTS = 16
ROUND_RIM = 0.8
ROUND_RIM_SHARE = 0.25
ROUND_CORNER = 1.7
ROUND_TURN_DEG = 5
TALL_RATIO = 2.0
BOX_RATIO = 2.5

# how each stored word is said before "object" in an answer
SAID = {"panel": "thin upright"}


def shape_class(size: Sequence[float], points: Optional[Sequence[float]] = None,
                basis: Optional[np.ndarray] = None, centre: Optional[Sequence[float]] = None) -> Optional[str]:
    """Rule "shape class" (module docstring) from a gravity-aligned size (w, d, h: along the
    rows e1, e2, up of `basis`, metres) and, where given, surface points (world frame, flat x, y,
    z, ...) around the box `centre` (world frame): flat, panel, round, tall, box-shaped or None."""
    w, d, h = (float(v) for v in size)
    long_side, short_side = max(w, d), min(w, d)
    if h <= FLAT_MAX_M + ROUNDING_M and h < FLAT_RATIO * short_side:
        return "flat"
    if short_side < PANEL_RATIO * long_side and h > short_side:
        return "panel"
    if _round_footprint(w, d, points, basis, centre):
        return "round"
    if h >= TALL_RATIO * long_side:
        return "tall"
    if max(w, d, h) <= BOX_RATIO * max(min(w, d, h), 1e-3):
        return "box-shaped"
    return None


def _round_footprint(w: float, d: float, points: Any, basis: Any, centre: Any) -> bool:
    """The round test of `shape_class`: the points' horizontal offsets over the half sides of
    their own smallest rectangle show an outline and never reach its corners."""
    if points is None or basis is None or centre is None or min(w, d) < ROUND_MIN_M \
            or max(w, d) > ROUND_SQUARE * min(w, d):
        return False
    pts = np.asarray(points, float).reshape(-1, 3)
    if len(pts) < ROUND_MIN_POINTS:
        return False
    rel = _in_own_rectangle((pts - np.asarray(centre, float)) @ np.asarray(basis, float)[:2].T)
    rim = np.hypot(rel[:, 0], rel[:, 1]) >= ROUND_RIM
    corner = np.abs(rel).sum(axis=1) > ROUND_CORNER
    return bool(rim.mean() >= ROUND_RIM_SHARE and not corner.any())


def _in_own_rectangle(xy: np.ndarray) -> np.ndarray:
    """Horizontal points as offsets from the centre of their smallest-area rectangle (turned in
    ROUND_TURN_DEG steps) over its half sides: each coordinate within [-1, 1]."""
    def turned(deg: int) -> np.ndarray:
        a = np.radians(deg)
        return xy @ np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])

    def area(deg: int) -> float:
        t = turned(deg)
        return float(np.prod(t.max(axis=0) - t.min(axis=0)))

    best = turned(min(range(0, 90, ROUND_TURN_DEG), key=area))
    lo, hi = best.min(axis=0), best.max(axis=0)
    return (best - (lo + hi) / 2) / np.maximum((hi - lo) / 2, 1e-6)
