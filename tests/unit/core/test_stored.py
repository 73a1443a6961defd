"""The read side's shapes (sg3d.core.stored): the export's JSON form key for key, the scene as it
stands now, names added without touching the graph they were read from."""
from __future__ import annotations

import dataclasses

import pytest

from sg3d.core.stored import NODE_FIELDS, StoredGraph, StoredObject, StoredRelation


def _graph() -> StoredGraph:
    cup = StoredObject(id="c", room="home/kitchen", label="cup", x=1.0, y=0.0, z=0.8, room_name="kitchen")
    table = StoredObject(id="t", room="home/kitchen", label="dining table", room_name="kitchen")
    gone = StoredObject(id="g", room="home/kitchen", label="book", removed_at=5.0, room_name="kitchen")
    return StoredGraph("home", "kitchen", [cup, table, gone],
                       [StoredRelation("c", "ON", "t", 0.9, 2), StoredRelation("g", "ON", "t", 0.8, 1)])


def test_an_object_as_json_lists_every_stored_field_then_only_what_the_read_added():
    plain = StoredObject(id="c", label="cup", room_name="kitchen").as_json()
    assert list(plain) == [*NODE_FIELDS, "room_name"]
    assert plain["colour"] is None and plain["label"] == "cup"
    full = StoredObject(id="c", hist=[0.5], thumbnail_jpeg_base64="/9j", name="cup").as_json()
    assert list(full)[len(NODE_FIELDS) + 1:] == ["hist", "thumbnail_jpeg_base64", "name"]


def test_a_graph_as_json_is_the_export_form():
    data = _graph().as_json()
    assert list(data) == ["building", "room", "nodes", "edges"]
    assert data["edges"][0] == {"s": "c", "type": "ON", "o": "t", "score": 0.9, "count": 2}
    with_frames = dataclasses.replace(_graph(), room_transforms={"kitchen": None}).as_json()
    assert list(with_frames)[-1] == "room_transforms"


def test_present_leaves_out_removed_objects_and_their_edges():
    now = _graph().present()
    assert [n.id for n in now.nodes] == ["c", "t"]
    assert [(e.s, e.o) for e in now.edges] == [("c", "t")]
    kept = StoredGraph("home", None, [StoredObject(id="c")])
    assert kept.present() is kept


def test_named_gives_a_new_graph_and_leaves_the_read_one_as_it_was():
    g = _graph()
    named = g.named({"c": "white cup", "t": "dining table", "g": "book"})
    assert [n.name for n in named.nodes] == ["white cup", "dining table", "book"]
    assert all(n.name is None for n in g.nodes)
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.nodes[0].name = "x"     # type: ignore[misc]
