"""Viewpoint relations computed at query time, and "where is X" as one sentence (real store)."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.graphdb.merge import merge_local_graph
from sg3d.queries.reader.grammar import read
from sg3d.queries.reader.tidy import tidy
from sg3d.queries.viewpoint import describe_place, viewpoint_relations
from sg3d.queries.vqa import answer
from tests.factories import graph, hist_of, obj

UP = (0.0, 0.0, 1.0)


def box(x, y, z, w, d, h):
    return {"box_centre": [x, y, z], "size": [w, d, h]}


TABLE = box(0.0, 0.0, 0.375, 1.6, 0.9, 0.75)
CHAIR = box(0.0, -0.8, 0.45, 0.45, 0.45, 0.9)       # on the table's south side
LAMP = box(1.3, 0.0, 0.5, 0.3, 0.3, 1.0)            # east of the table


def test_front_and_behind_flip_with_the_viewpoint():
    south, north = (0.0, -3.0, 1.2), (0.0, 3.0, 1.2)
    assert viewpoint_relations(CHAIR, TABLE, south, UP) == {"IN_FRONT_OF"}
    assert viewpoint_relations(CHAIR, TABLE, north, UP) == {"BEHIND"}
    assert viewpoint_relations(TABLE, CHAIR, south, UP) == {"BEHIND"}
    # looking north (+y) with z up, east is on the right; looking south it is on the left
    assert viewpoint_relations(LAMP, TABLE, south, UP) == {"RIGHT_OF"}
    assert viewpoint_relations(LAMP, TABLE, north, UP) == {"LEFT_OF"}
    # seen from the east the lamp is in front of the table, the chair neither in front nor behind
    east = (4.0, 0.0, 1.2)
    assert viewpoint_relations(LAMP, TABLE, east, UP) == {"IN_FRONT_OF"}
    assert not {"IN_FRONT_OF", "BEHIND"} & viewpoint_relations(CHAIR, TABLE, east, UP)


def test_viewpoint_phrase_is_read_by_the_grammar():
    form = read(tidy("is there a chair in front of the table as seen from the sink?").text)
    assert form.seen_from is not None and form.seen_from.text() == "sink"
    assert form.sets[0].filters[0].relation == "in front of"
    form = read(tidy("how many chairs are behind the table, viewed from the tv").text)
    assert form.seen_from is not None and form.seen_from.text() == "tv" and form.filters[0].relation == "behind"
    assert read(tidy("where is the cup?").text).seen_from is None


def test_where_sentence_gives_support_first_and_names_others_once():
    rows = [{"rel": "NEAR", "other_id": "k", "other_label": "chair", "other_colour": "black", "rel_score": 0.9},
            {"rel": "NEXT_TO", "other_id": "c2", "other_label": "cup", "other_colour": "white", "rel_score": 0.7},
            {"rel": "ON", "other_id": "t", "other_label": "dining table", "other_colour": "brown", "rel_score": 0.8},
            {"rel": "NEXT_TO", "other_id": "m", "other_label": "book", "other_colour": None, "rel_score": 0.8},
            {"rel": "NEXT_TO", "other_id": "v", "other_label": "vase", "other_colour": "blue", "rel_score": 0.2}]
    assert describe_place(rows) == "on the brown dining table, next to the book and the white cup"


@pytest.fixture
def room(store):
    hist = hist_of({30: 500})
    merge_local_graph(store, graph([
        obj("t", "dining table", (0.0, 0.0, 0.375), size=(1.6, 0.9, 0.75), hist=hist, colour="brown"),
        obj("h", "chair", (0.0, -0.8, 0.45), size=(0.45, 0.45, 0.9), hist=hist_of({200: 100}), colour="black"),
        obj("s", "sink", (0.0, -3.0, 0.85), size=(0.5, 0.4, 0.2), hist=hist_of({300: 100}), colour="grey"),
        obj("c", "cup", (0.2, 0.1, 0.8), size=(0.08, 0.08, 0.1)),
    ], relations=[("c", "ON", "t", 0.9), ("h", "NEXT_TO", "t", 0.8), ("t", "BIGGER_THAN", "c", 0.9)]))
    return store


def test_in_front_of_is_answered_from_a_named_object_or_a_callers_viewpoint(room):
    a = answer(room, "is there a chair in front of the table as seen from the sink?")
    assert a.ok and a.value is True, a.text
    a = answer(room, "is there a chair behind the table as seen from the sink?")
    assert a.ok and a.value is False, a.text
    # the observer is not among what it sees in front of the table
    a = answer(room, "what is in front of the dining table as seen from the sink?")
    assert a.ok and [o["label"] for o in a.value] == ["chair"], a.text
    # a robot standing north of the table passes its pose: the chair is behind the table
    pose = np.eye(4)
    pose[:3, 3] = (0.0, 3.0, 1.2)
    a = answer(room, "how many chairs are behind the table?", viewpoint={"pose": pose.tolist()})
    assert a.ok and a.value == 1, a.text
    a = answer(room, "how many chairs are behind the table?", viewpoint={"position": [0.0, -3.0, 1.2]})
    assert a.ok and a.value == 0, a.text
    a = answer(room, "is there a chair to the left of the table?", viewpoint={"position": [3.0, 0.0, 1.2]})
    assert a.ok and a.value is True, a.text       # looking west, south is on the left
    # without a viewpoint the question cannot be answered, and says how to give one
    a = answer(room, "is there a chair in front of the table?")
    assert not a.ok and "as seen from" in a.text


def test_where_is_the_cup_is_one_coherent_sentence(room):
    a = answer(room, "where is the cup?")
    assert a.ok
    assert "the cup is on the dining table, in the kitchen" in a.text   # one table: named without colour
    assert "front" not in a.text and "behind" not in a.text
