"""Questions across the rooms of one building: which room, whole-building counts with
an object seen from two rooms (SAME_AS) counted once, a room by name. Real embedded store."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.graphdb.building import link_rooms
from sg3d.graphdb.merge import merge_local_graph
from sg3d.queries.vqa import answer
from tests.factories import graph, obj


@pytest.fixture
def linked(store):
    """kitchen: 2 chairs + sink; hall: 1 chair + couch. The hall's frame is the kitchen's shifted
    by -5 m in x, so the hall's chair at x=0 is the kitchen's chair at x=5: one chair, two views."""
    kitchen = graph([obj("c1", "chair", (1, 0, 0), colour="red"), obj("c2", "chair", (5, 0, 0), colour="red"),
                     obj("sk", "sink", (2, 1, 3), colour="grey")], room="kitchen", building="home")
    hall = graph([obj("c3", "chair", (0, 0, 0), colour="red"), obj("s", "couch", (3, 0, 4), colour="grey")],
                 room="hall", building="home")
    merge_local_graph(store, kitchen)
    merge_local_graph(store, hall)
    T = np.eye(4)
    T[0, 3] = 5.0                      # hall frame -> kitchen frame
    report = link_rooms(store, "home/kitchen", "home/hall", transform=T)
    assert len(report.same_as) == 1    # the shared chair, nothing else
    return store


def ok(store, q, **kw):
    a = answer(store, q, **kw)
    assert a.ok, a.text
    return a


@pytest.mark.parametrize("scope", ["in the house", "in the building", "in the home", ""])
def test_whole_building_counts_one_physical_object_once(linked, scope):
    a = ok(linked, f"how many chairs are there {scope}?".replace("  ", " "))
    assert a.value == 2 and "counted once" in a.text
    assert ok(linked, f"how many chairs {scope}", building="home").value == 2


def test_room_by_name_counts_its_own_views(linked):
    assert ok(linked, "how many chairs are in the kitchen?").value == 2
    assert ok(linked, "how many chairs are in the hall?").value == 1
    assert ok(linked, "how many chairs", room="hall").value == 1


def test_which_room(linked):
    a = ok(linked, "which room has a sink?")
    assert a.form == "rooms" and [r["room"] for r in a.value] == ["home/kitchen"]
    a = ok(linked, "which rooms have chairs?")
    assert {r["room"]: r["n"] for r in a.value} == {"home/kitchen": 2, "home/hall": 1}
    assert "2 chairs in all" in a.text
    assert [r["room"] for r in ok(linked, "in which room is the couch?").value] == ["home/hall"]
    assert ok(linked, "which room has a toaster?").value == []
    assert not answer(linked, "which room has a chair?", building="elsewhere").ok


def test_compositional_counts_also_count_one_physical_object_once(linked):
    a = ok(linked, "how many objects are there?")             # any object: the compiler's count
    assert a.value == 4 and "counted once" in a.text
    a = ok(linked, "how many red things are there?")
    assert a.value == 2 and "counted once" in a.text
    assert ok(linked, "which rooms are next to the kitchen?").value == ["hall"]
