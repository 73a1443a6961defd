"""Room and building names (`sg3d.app.bounds.name_problem`): the rule every front end applies."""
from __future__ import annotations

import pytest

from sg3d.app.bounds import name_problem


@pytest.mark.parametrize("name", [".", "..", "...", ". .", ".\u00a0.", "", " ", "a/b", "a\\b", "a..b", " lab"])
def test_dots_separators_and_blank_names_are_refused(name):
    assert name_problem(name, "room") is not None


@pytest.mark.parametrize("name", ["lab", "küche", "my room", "v1.2", ".lab", "lab.", "a.b.c"])
def test_ordinary_names_with_single_dots_pass(name):
    assert name_problem(name, "room") is None


def test_a_build_or_map_request_refuses_a_dot_for_a_room_or_building():
    from sg3d.app.build import BuildError, check_names
    from sg3d.app.errors import MapError

    with pytest.raises(BuildError, match="more than dots"):
        check_names(".", "default")
    with pytest.raises(MapError, match="more than dots"):
        check_names("lab", ". .", MapError)
    check_names("lab", "default")
