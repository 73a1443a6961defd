"""Rule "a room keeps its heading" (`sg3d.app.build.kept_heading`): a later build into a room
measures its boxes along the axes the room's boxes were measured along."""
from __future__ import annotations

from sg3d.app.build import kept_heading
from sg3d.core.geometry import Ground

UP = (0.0, 0.0, 1.0)
THIS = (0.96, 0.28, 0.0)          # this build's estimate
STORED = (0.94, 0.34, 0.0)


def test_a_new_room_takes_this_builds_heading():
    assert kept_heading(Ground(UP, 0.0, THIS), []).heading == THIS
    assert kept_heading(Ground(UP, 0.0, THIS), [{"id": "b/r", "up": None, "heading": None}]).heading == THIS


def test_a_room_built_before_keeps_its_stored_heading():
    assert kept_heading(Ground(UP, 0.0, THIS), [{"id": "b/r", "up": list(UP), "heading": list(STORED)}]).heading == STORED
    assert kept_heading(Ground(UP, 0.0, None), [{"id": "b/r", "up": list(UP), "heading": list(STORED)}]).heading == STORED


def test_a_room_built_before_headings_keeps_the_worlds_axes():
    assert kept_heading(Ground(UP, 0.0, THIS), [{"id": "b/r", "up": list(UP), "heading": None}]).heading is None
