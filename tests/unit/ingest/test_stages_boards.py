"""What rests on a board rests on its frame (`sg3d.ingest.stages.on_the_frames_of_boards`)."""
from __future__ import annotations

import numpy as np

from sg3d.core.model import ObjectObservation, RelationObservation
from sg3d.ingest import stages

UP = (0.0, 0.0, 1.0)


def _obs(local_id: str, label: str, centre, size, layer: str = "object") -> ObjectObservation:
    return ObjectObservation(local_id, [label], [1.0], tuple(centre), (0.0, 0.0, 0.0), 100, tuple(size),
                             np.zeros(8), box_centre=tuple(centre), layer=layer)


def test_a_thing_on_a_bookcase_board_is_on_the_bookcase():
    case = _obs("case", "object", (0.5, 0.2, 0.7), (1.0, 0.35, 1.4))
    board = _obs("board", "shelf", (0.5, 0.2, 0.435), (0.9, 0.3, 0.03), layer="structure")
    cup = _obs("cup", "cup", (0.3, 0.2, 0.5), (0.08, 0.08, 0.1))
    on = [RelationObservation("cup", "ON", "board", 0.9)]
    assert stages.on_the_frames_of_boards(on, [case, board, cup], UP) == [RelationObservation("cup", "ON", "case", 0.9)]


def test_a_surface_that_is_no_frames_board_adds_nothing():
    table = _obs("table", "dining table", (3.0, 0.0, 0.37), (1.2, 0.8, 0.74))
    top = _obs("top", "surface", (3.0, 0.0, 0.735), (1.2, 0.8, 0.03), layer="structure")   # its own top
    cup = _obs("cup", "cup", (3.0, 0.0, 0.8), (0.08, 0.08, 0.1))
    assert stages.on_the_frames_of_boards([RelationObservation("cup", "ON", "top")], [table, top, cup], UP) == []
