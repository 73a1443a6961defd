"""What has no name, asked about: a desk room merged into the real store through the real merge
path, with a flat black 45 x 14 x 2 cm unnamed slab on the desk. "is there a keyboard?" names no
keyboard but lists that slab as unnamed (sg3d/queries/unnamed.py); things of another size, shape
or support are not listed, and the slab stays unnamed in the store."""
from __future__ import annotations

from dataclasses import replace

import pytest

from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from sg3d.queries.vqa import answer
from tests.cli_helpers import sg3d
from tests.factories import graph, hist_of, obj

ROOM = "office"
SLAB = "a flat black object 45x14 cm on the desk"


def _desk_room():
    floor = replace(obj("floor", "floor", (0, 0, -0.01), size=(4.0, 4.0, 0.02), colour="grey",
                        hist=hist_of({3: 100})), layer="structure")
    return graph([
        floor,
        obj("desk", "desk", (0, 0, 0.375), size=(1.4, 0.7, 0.75), colour="brown", hist=hist_of({30: 100})),
        obj("slab", "object", (0.1, 0.0, 0.76), size=(0.45, 0.14, 0.02), colour="black", hist=hist_of({0: 100})),
        # box-shaped: no keyboard
        obj("box", "object", (-0.4, 0.1, 0.85), size=(0.30, 0.25, 0.20), colour="grey", hist=hist_of({5: 100})),
        # keyboard-sized and flat, but on the floor: a keyboard lies on a surface
        obj("mat", "object", (1.5, 1.5, 0.01), size=(0.45, 0.14, 0.02), colour="white", hist=hist_of({9: 100})),
        # flat and on the desk, but its long side over twice a keyboard's
        obj("board", "object", (0.0, 0.25, 0.76), size=(1.0, 0.30, 0.02), colour="black", hist=hist_of({1: 100})),
    ], relations=[("desk", "ON", "floor", 0.9), ("slab", "ON", "desk", 0.9), ("box", "ON", "desk", 0.9),
                  ("mat", "ON", "floor", 0.9), ("board", "ON", "desk", 0.8)], room=ROOM, building="home")


def _merged(store, g):
    """The local graph merged into the store (up: +z); its local ids -> node ids."""
    g.up = (0.0, 0.0, 1.0)
    return merge_local_graph(store, g).node_ids


@pytest.fixture
def desk_room(store):
    return _merged(store, _desk_room())


def test_is_there_a_keyboard_lists_the_unnamed_slab(desk_room, store, embedded_home):
    out = sg3d(embedded_home, "ask", "is there a keyboard?", "--room", ROOM)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == f"I have not named a keyboard; an unnamed thing of its size and shape: {SLAB}"
    # the slab keeps no guessed name: the store still calls it unnamed, and flat
    rows = [r["o"] for r in store.read("object_all", room=room_id("home", ROOM))]
    slab = [r for r in rows if r["id"] == desk_room["slab"]][0]
    assert slab["label"] == "object" and slab["shape"] == "flat"


def test_how_many_and_where_say_none_named(desk_room, store):
    a = answer(store, "how many keyboards are there?", room=ROOM)
    assert a.text == f"0 named keyboards; 1 unnamed thing could be one: {SLAB}", a.text
    assert a.value == 0 and a.absent_evidence
    w = answer(store, "where is the keyboard?", room=ROOM)
    assert w.text == f"I have not named a keyboard; an unnamed thing of its size and shape: {SLAB}", w.text
    assert [o["id"] for o in w.objects] == [desk_room["slab"]] and w.objects[0]["could_be"] == "keyboard"
    e = answer(store, "is there a keyboard?", room=ROOM)
    assert e.value is False and e.absent_evidence and e.provenance[0]["id"] == desk_room["slab"]


def test_no_candidate_keeps_the_plain_answer(desk_room, store):
    # a phone is a tenth of the slab's area: nothing of its size; a white keyboard: only the mat,
    # which lies on the floor
    for q, what in (("is there a cell phone?", "a cell phone"), ("is there a white keyboard?", "a keyboard")):
        a = answer(store, q, room=ROOM)
        assert a.text.startswith(f"I have not found {what}") and "unnamed" not in a.text, a.text
    # a named keyboard is counted as before, and the slab is not added to it
    merge_local_graph(store, graph([obj("kb", "keyboard", (0.1, 0.3, 0.77), size=(0.44, 0.13, 0.03),
                                        colour="white", hist=hist_of({11: 100}))], room=ROOM, building="home"))
    a = answer(store, "is there a keyboard?", room=ROOM)
    assert a.text.startswith("yes, 1 keyboard"), a.text



def test_other_phrasings_say_the_same(desk_room, store):
    said = f"I have not named a keyboard; an unnamed thing of its size and shape: {SLAB}"
    for q in ("where is every keyboard?", "is there any keyboard around here?", "do we have a keyboard?"):
        assert answer(store, q, room=ROOM).text == said, q
    # a kind with no typical size is never guessed
    assert answer(store, "is there a sink?", room=ROOM).text.startswith("I have not found a sink")


def test_a_desk_top_no_one_named_is_a_surface(store):
    """A desk scan that never saw the floor keeps its desk top as an unnamed object: what lies on
    it, wider and deeper than it, rests on a surface."""
    g = graph([
        obj("top", "object", (0, 0, 0.37), size=(1.3, 0.7, 0.74), colour="brown", hist=hist_of({30: 100})),
        obj("slab", "object", (0.1, 0.0, 0.75), size=(0.45, 0.14, 0.02), colour="black", hist=hist_of({0: 100})),
    ], relations=[("slab", "ON", "top", 0.9)], room="scan", building="home")
    g.up = (0.0, 0.0, 1.0)
    merge_local_graph(store, g)
    a = answer(store, "is there a keyboard?", room="scan")
    assert a.text == ("I have not named a keyboard; an unnamed thing of its size and shape: a flat black object "
                      "45x14 cm on a brown object 130x70 cm"), a.text


def _desk_scan():
    """A desk scanned from above: no floor, no desk named; its top an unnamed flat object with a
    cup and an unnamed box ON it, and a small flat sheet with nothing on it."""
    return graph([
        obj("top", "object", (0, 0, 0.0), size=(1.2, 0.55, 0.03), colour="black", hist=hist_of({0: 100})),
        obj("cup", "cup", (0.2, 0.1, 0.06), size=(0.08, 0.08, 0.10), colour="red", hist=hist_of({11: 100})),
        obj("box", "object", (-0.3, 0.0, 0.09), size=(0.25, 0.20, 0.15), colour="blue", hist=hist_of({20: 100})),
        obj("sheet", "object", (1.0, 1.0, 0.0), size=(0.30, 0.21, 0.01), colour="white", hist=hist_of({9: 100})),
    ], relations=[("cup", "ON", "top", 0.9), ("box", "ON", "top", 0.9)], room="scan", building="home")


@pytest.fixture
def desk_scan(store):
    return _merged(store, _desk_scan())


def test_what_is_on_the_desk_lists_what_stands_on_an_unnamed_top(desk_scan, store, embedded_home):
    out = sg3d(embedded_home, "ask", "what is on the desk?", "--room", "scan")
    assert out.returncode == 0, out.stderr
    text = out.stdout.strip()
    assert text.startswith("I have not named a desk in the scan; on an unnamed flat black object 120x55 cm "
                           "that could be its top: "), text
    assert "the cup" in text and "box-shaped" in text, text
    assert "white" not in text, text                    # the sheet stands on nothing
    rows = [r["o"] for r in store.read("object_all", room=room_id("home", "scan"))]
    top = [r for r in rows if r["id"] == desk_scan["top"]][0]
    assert top["label"] == "object"                     # the top keeps no guessed name
