"""Geometry every layer shares: the gravity-aligned frame boxes are measured in, the kinds of
furniture that stand on the floor, and the part-of-furniture rules both a build
(`sg3d.ingest.discover`) and the merge of a later scan (`sg3d.merge.plan`) apply."""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

# Furniture that stands on the floor by its kind: two of them are on one level even when their
# boxes say otherwise (a chair at a table is seen above the table top, or down to the floor).
FLOOR_STANDING_LABELS = frozenset({
    "chair", "couch", "bed", "dining table", "bench", "toilet", "refrigerator", "oven",
    "desk", "cabinet",
})
# Kinds that stand solid to the floor (no knee space under them): a refrigerator, an oven. A desk
# named from its shape had the floor seen under its top, so it is none of them.
SOLID_TO_THE_FLOOR = frozenset({"refrigerator", "oven"})


# Decimals a value keeps where one stage of a build hands it to the next (`fixed_precision`):
# positions and sizes in metres (1 um), directions (unit vectors).
METRES_DECIMALS = 6
DIRECTION_DECIMALS = 12


def fixed_precision(values: ArrayLike, decimals: int = METRES_DECIMALS) -> np.ndarray:
    """Rule "a fixed precision between stages": `values` rounded to `decimals` decimals. Another
    CPU's kernels (BLAS, SIMD) or another thread split change a float's last bits; rounded where a
    stage hands it on, the next stage gets the same number on every machine (unless it lies within
    those bits of a rounding boundary: about one value in 1e8)."""
    return np.round(np.asarray(values, dtype=np.float64), decimals) + 0.0   # + 0.0: no -0.0


def horizontal_basis(up: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A right-handed orthonormal frame (e1, e2, up) with e1, e2 horizontal.

    e1 is the world x axis made horizontal (world y if x is nearly vertical), so the same
    `up` always gives the same frame: sizes computed by other modules in this frame agree. The
    vectors are kept to DIRECTION_DECIMALS (`fixed_precision`), so they are the same on any CPU.
    """
    u = np.asarray(up, dtype=np.float64)
    u = u / math.hypot(*(float(v) for v in u))
    seed = np.array([1.0, 0.0, 0.0]) if abs(u[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = seed - float(seed[0] * u[0] + seed[1] * u[1] + seed[2] * u[2]) * u
    e1 /= math.hypot(*(float(v) for v in e1))
    e2 = np.cross(u, e1)
    return tuple(fixed_precision(v, DIRECTION_DECIMALS) for v in (e1, e2, u))  # type: ignore[return-value]


def horizontal_frame(up: ArrayLike) -> np.ndarray:
    """`horizontal_basis(up)` as the rows of one 3x3 matrix (e1, e2, up): `points @ frame.T` gives
    each point's coordinates along e1, e2 and up."""
    return np.stack(horizontal_basis(up))


def gravity_basis(up: Optional[ArrayLike]) -> np.ndarray:
    """Rows e1, e2, up of a room's gravity frame (`horizontal_frame`); the world axes when the
    room has no up, so sizes measured along them stay axis-aligned."""
    return np.eye(3) if up is None else horizontal_frame(up)


# The kind of node a carrel's panels belong to (`sg3d.ingest.discover.furniture.DESK_LABEL`).
DESK_LABEL = "desk"
# A carrel's side panel: a piece at most CARREL_PANEL_MAX_THICKNESS_M thick along one horizontal
# axis (a partition is 3-8 cm thick; seen edge-on with its trim and 1-3 cm depth noise its segment
# measures up to 0.15 m), within CARREL_REACH_M of a worktop's footprint and rising above the top.
# Side panels stand beside a top's ends (0.1-0.2 m off in the study room) and run past its front
# edge: a carrel's panel is 0.8-1.0 m deep against a 0.6-0.75 m top, and the top is measured from
# what was seen of it, so a panel's front end seen alone lies up to ~0.35 m before it (0.31 m in the
# study room's second fragment). A chair is not that thin; a cabinet or a wall does not stand there.
CARREL_PANEL_MAX_THICKNESS_M = 0.20
# Segment sizes are whole numbers of 2.5 cm voxels summed in floating point: a 0.20 m side may
# read 0.2000000001; limits are compared with a millimetre of slack.
SIZE_SLACK_M = 0.001
CARREL_REACH_M = 0.40


def boxes_touch(lo: np.ndarray, hi: np.ndarray, lo2: np.ndarray, hi2: np.ndarray, margin: float) -> bool:
    """Whether two gravity boxes' footprints (their first two axes) lie within `margin` of each other."""
    return bool((lo[:2] - margin <= hi2[:2]).all() and (lo2[:2] <= hi[:2] + margin).all())


def carrel_panel(lo: np.ndarray, hi: np.ndarray, top_lo: np.ndarray, top_hi: np.ndarray) -> bool:
    """Rule "a carrel's panel": a piece (gravity box lo, hi) at most CARREL_PANEL_MAX_THICKNESS_M
    thick along a horizontal axis, within CARREL_REACH_M of a desk's box (top_lo, top_hi: from the
    floor to its top, `sg3d.ingest.discover.furniture.desk_box`) and rising above its top is a side
    panel of the carrel, part of the desk. Heights only compare with each other, so any one
    vertical origin serves (the floor in a build, the world's in a merge)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    top_lo, top_hi = np.asarray(top_lo, float), np.asarray(top_hi, float)
    thin = float(np.min(hi[:2] - lo[:2])) <= CARREL_PANEL_MAX_THICKNESS_M + SIZE_SLACK_M
    return (thin and float(hi[2]) > float(top_hi[2])
            and boxes_touch(lo, hi, top_lo, top_hi, CARREL_REACH_M))


@dataclass(frozen=True)
class Ground:
    """The room's gravity frame: its up direction (world frame) and the floor's height along it,
    when the build knows it."""

    up: Any                         # 3-vector
    floor: Optional[float] = None

    @functools.cached_property
    def basis(self) -> np.ndarray:
        return horizontal_frame(self.up)
