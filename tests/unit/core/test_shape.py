"""Rule "shape class" (sg3d/core/shape.py): every threshold pinned on both sides, and the merge
storing it for unnamed objects only."""
from __future__ import annotations

import math

import numpy as np
import pytest

from sg3d.core import shape
from sg3d.core.shape import shape_class
from sg3d.merge.plan import stored_shape

BASIS = np.eye(3)          # rows e1, e2, up
CENTRE = (0.0, 0.0, 0.2)


def ring(n: int, half=(0.15, 0.15), r: float = 1.0) -> list[float]:
    """n points on an ellipse of the half sides (times r) around CENTRE, flat x, y, z."""
    out = []
    for k in range(n):
        a = 2 * math.pi * k / n
        out += [CENTRE[0] + r * half[0] * math.cos(a), CENTRE[1] + r * half[1] * math.sin(a), 0.2]
    return out


def square(n: int, half: float = 0.15) -> list[float]:
    """n points along a square outline of half side `half`."""
    out = []
    for k in range(n):
        t = 8 * k / n - 4      # once round the outline
        side, s = int((t + 4) // 2), (t + 4) % 2 - 1
        x, y = [(1, s), (-s, 1), (-1, -s), (s, -1)][side % 4]
        out += [x * half, y * half, 0.2]
    return out


@pytest.mark.parametrize("size, word", [
    ((0.45, 0.14, 0.02), "flat"),             # a keyboard
    ((0.45, 0.30, 0.05), "flat"),             # at FLAT_MAX_M
    ((0.45, 0.30, 0.050000000000000024), "flat"),  # two 2.5 cm voxels as a build measures them
    ((0.45, 0.30, 0.050002), None),
    ((0.45, 0.30, 0.051), None),              # above it: too tall to lie flat, too low for a box
    ((0.10, 0.10, 0.0249), "flat"),           # below FLAT_RATIO of the smaller side
    ((0.10, 0.10, 0.025), None),              # at it: a small cube is no slab
    ((0.45, 0.08, 0.025), None),              # the SMALLER side decides: a bar is not flat
])
def test_flat(size, word):
    assert shape_class(size) == word


@pytest.mark.parametrize("size, word", [
    ((0.60, 0.1499, 0.40), "panel"),          # thin side under PANEL_RATIO of the other
    ((0.60, 0.1501, 0.40), None),             # over it
    ((0.60, 0.05, 0.051), "panel"),           # taller than its thin side: on edge
    ((0.60, 0.05, 0.05), None),               # no taller than its thin side: a bar
    ((0.60, 0.06, 0.06), None),               # a bar lying down: neither
])
def test_panel(size, word):
    assert shape_class(size) == word


@pytest.mark.parametrize("size, word", [
    ((0.10, 0.10, 0.20), "tall"),             # TALL_RATIO times the longer side
    ((0.10, 0.10, 0.199), "box-shaped"),
    ((0.30, 0.25, 0.12), "box-shaped"),       # sides within BOX_RATIO
    ((0.30, 0.25, 0.119), None),
    ((1.4, 1.2, 0.2), None),                  # a low slab: nothing said
])
def test_tall_and_box(size, word):
    assert shape_class(size) == word


def test_round_needs_an_outline_that_never_reaches_the_corners():
    size = (0.30, 0.30, 0.40)
    assert shape_class(size, ring(32), BASIS, CENTRE) == "round"
    assert shape_class(size, square(32), BASIS, CENTRE) == "box-shaped"
    assert shape_class(size) == "box-shaped"                       # no points: a box says nothing of roundness
    # ROUND_CORNER: one point past |u| + |v| = 1.7 is a corner
    for s, word in ((1.69, "round"), (1.71, "box-shaped")):
        corner = [s / 2 * 0.15, s / 2 * 0.15, 0.2]
        assert shape_class(size, ring(31) + corner, BASIS, CENTRE) == word
    # ROUND_MIN_POINTS
    assert shape_class(size, ring(shape.ROUND_MIN_POINTS), BASIS, CENTRE) == "round"
    assert shape_class(size, ring(shape.ROUND_MIN_POINTS - 1), BASIS, CENTRE) == "box-shaped"
    # ROUND_RIM_SHARE of the points at ROUND_RIM or beyond: an outline, not a blob at the centre
    inner = ring(24, r=0.7)
    assert shape_class(size, inner + ring(8), BASIS, CENTRE) == "round"            # 8 of 32 on the rim
    assert shape_class(size, inner + ring(7), BASIS, CENTRE) == "box-shaped"       # 7 of 31


def test_round_needs_a_large_square_footprint():
    assert shape_class((0.20, 0.20, 0.30), ring(32, (0.10, 0.10)), BASIS, CENTRE) == "round"
    assert shape_class((0.199, 0.199, 0.30), ring(32, (0.0995, 0.0995)), BASIS, CENTRE) == "box-shaped"
    # ROUND_SQUARE: the longer side at most 1.2 times the shorter
    assert shape_class((0.30, 0.2501, 0.40), ring(32, (0.15, 0.12505)), BASIS, CENTRE) == "round"
    assert shape_class((0.30, 0.2499, 0.40), ring(32, (0.15, 0.12495)), BASIS, CENTRE) == "box-shaped"


def test_round_reads_the_points_in_the_gravity_frame():
    up = np.array([0.0, -1.0, 0.0])          # a y-down world, as a camera's frame is
    basis = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], up])
    centre = np.array([1.0, -0.5, 2.0])
    pts = []
    for k in range(32):
        a = 2 * math.pi * k / 32
        pts += list(centre + 0.15 * math.cos(a) * basis[0] + 0.15 * math.sin(a) * basis[1])
    assert shape_class((0.30, 0.30, 0.40), pts, basis, centre) == "round"


def test_the_merge_stores_a_shape_for_unnamed_objects_only():
    slab = (0.45, 0.14, 0.02)
    assert stored_shape("object", "object", slab, None, BASIS, CENTRE, "box-shaped") == "flat"
    assert stored_shape("keyboard", "object", slab, None, BASIS, CENTRE, None) is None
    assert stored_shape("object", "structure", slab, None, BASIS, CENTRE, None) is None


def test_a_box_turned_against_the_rooms_axes_is_no_disc():
    """Its points never reach the corners of the room-aligned box around it, but do reach those
    of their own smallest rectangle."""
    c, s = math.cos(math.pi / 4), math.sin(math.pi / 4)
    pts = square(32, 0.15)
    turned = []
    for k in range(0, len(pts), 3):
        x, y = pts[k], pts[k + 1]
        turned += [c * x - s * y, s * x + c * y, 0.2]
    side = 0.3 * math.sqrt(2)
    assert shape_class((side, side, 0.40), turned, BASIS, CENTRE) == "box-shaped"
    # a disc turned anyhow stays one
    assert shape_class((0.30, 0.30, 0.40), ring(32)[3:] + ring(32)[:3], BASIS, CENTRE) == "round"
