"""`sg3d rooms` says which frame each room is in ('reference frame' / 'placed in the building' /
'own frame'), not whether a transform is stored (no store: the rows are data)."""
from __future__ import annotations

import numpy as np

from sg3d.app.rooms import frame_words


def test_each_room_says_its_frame():
    moved = np.eye(4)
    moved[:3, 3] = (4.0, 0.5, 0.0)
    assert frame_words(None) == "own frame (not placed in the building)"
    assert frame_words(np.eye(4)) == "the building's reference frame"
    assert frame_words(moved) == "placed in the building's frame"
    assert "transform" not in frame_words(None) + frame_words(np.eye(4)) + frame_words(moved)
