"""Geometry every layer shares: the gravity-aligned frame boxes are measured in, and the kinds of
furniture that stand on the floor."""
from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

# Furniture that stands on the floor by its kind: two of them are on one level even when their
# boxes say otherwise (a chair at a table is seen above the table top, or down to the floor).
FLOOR_STANDING_LABELS = frozenset({
    "chair", "couch", "bed", "dining table", "bench", "toilet", "refrigerator", "oven",
    "desk", "cabinet",
})


def horizontal_basis(up: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A right-handed orthonormal frame (e1, e2, up) with e1, e2 horizontal.

    e1 is the world x axis made horizontal (world y if x is nearly vertical), so the same
    `up` always gives the same frame: sizes computed by other modules in this frame agree.
    """
    u = np.asarray(up, dtype=np.float64)
    u = u / np.linalg.norm(u)
    seed = np.array([1.0, 0.0, 0.0]) if abs(u[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = seed - seed.dot(u) * u
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    return e1, e2, u


def horizontal_frame(up: ArrayLike) -> np.ndarray:
    """`horizontal_basis(up)` as the rows of one 3x3 matrix (e1, e2, up): `points @ frame.T` gives
    each point's coordinates along e1, e2 and up."""
    return np.stack(horizontal_basis(up))


def gravity_basis(up: Optional[ArrayLike]) -> np.ndarray:
    """Rows e1, e2, up of a room's gravity frame (`horizontal_frame`); the world axes when the
    room has no up, so sizes measured along them stay axis-aligned."""
    return np.eye(3) if up is None else horizontal_frame(up)
