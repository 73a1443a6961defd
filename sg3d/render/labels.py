"""Label placement without overlap, in display pixels.

Greedy candidate placement, the usual cartographic method: each label tries positions around
its anchor (right, left, above, below, the diagonals), then the same ring farther out with a
leader line back to the anchor, and takes the first position that overlaps no placed label, no
node marker and stays inside the plot. A label that finds none is not drawn; the caller lists
it instead (a number on the picture and the name in the side table). Nodes never move: the
diagram is a map, positions are the objects' floor positions.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike

Box = tuple[float, float, float, float]          # x0, y0, x1, y1 (display pixels, y up)

# unit directions: right, left, up, down, then the diagonals
DIRECTIONS = [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1)]
RINGS = (1.0, 2.0, 3.2, 4.6, 6.2)                   # radii in marker radii + label half-sizes


def overlaps(a: Box, b: Box) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


class Occupancy:
    """Placed boxes, with a coarse grid so a test costs only the boxes nearby."""

    def __init__(self, cell: float = 64.0):
        self.cell = cell
        self.grid: dict[tuple[int, int], list[Box]] = {}

    def _cells(self, b: Box):
        c = self.cell
        for i in range(int(b[0] // c), int(b[2] // c) + 1):
            for j in range(int(b[1] // c), int(b[3] // c) + 1):
                yield i, j

    def free(self, b: Box) -> bool:
        return not any(overlaps(b, o) for k in self._cells(b) for o in self.grid.get(k, ()))

    def add(self, b: Box) -> None:
        for k in self._cells(b):
            self.grid.setdefault(k, []).append(b)


@dataclass
class Placed:
    centre: tuple[float, float]
    box: Box
    leader: bool              # drawn away from its anchor: draw a line back to it


def place(anchor: Sequence[float], size: Sequence[float], occ: Occupancy, bounds: Box,
          gap: float = 4.0, rings: Sequence[float] = RINGS) -> Optional[Placed]:
    """The first free position for a `size` (w, h) label near `anchor`, or None; adds it to `occ`."""
    w, h = size
    ax, ay = anchor
    for k, r in enumerate(rings):
        for dx, dy in DIRECTIONS:
            cx = ax + dx * (w / 2 + gap * r + (r - 1) * 8)
            cy = ay + dy * (h / 2 + gap * r + (r - 1) * 6)
            box = (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2)
            if box[0] < bounds[0] or box[1] < bounds[1] or box[2] > bounds[2] or box[3] > bounds[3]:
                continue
            if occ.free(box):
                occ.add(box)
                return Placed((cx, cy), box, k > 0)
    return None


def place_on_segment(a: ArrayLike, b: ArrayLike, size: Sequence[float], occ: Occupancy,
                     bounds: Box, fractions=(0.5, 0.4, 0.6, 0.3, 0.7)) -> Optional[Placed]:
    """A free position for an edge label on the segment a-b (middle first), or None."""
    w, h = size
    pa, pb = np.asarray(a, float), np.asarray(b, float)
    for t in fractions:
        cx, cy = pa + (pb - pa) * t
        box = (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2)
        if box[0] < bounds[0] or box[1] < bounds[1] or box[2] > bounds[2] or box[3] > bounds[3]:
            continue
        if occ.free(box):
            occ.add(box)
            return Placed((float(cx), float(cy)), box, False)
    return None
