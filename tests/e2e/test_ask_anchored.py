"""Forms read from the anchor outwards or by colour give the answers of the whole-room read, on a real store
(the house of tests/scenes.py): every field an asker sees, question by question, asked in the
kitchen and of the whole store (two rooms: read whole)."""
from __future__ import annotations

import pytest

from sg3d.app.ask import ask

SEEN = ("ok", "form", "answer", "value", "objects", "absent_evidence")
ANCHORED = ["what is on the table?", "how many things are on the table?", "what is next to the sink?",
            "is there anything on the table besides the cups?", "what is in the sink?",
            "how many objects are on the dining table?", "what is on the table other than the red cup?"]
COLOURED = ["what is red?", "how many red things are there?", "is there anything red on the table?",
            "what is white?", "which things are grey?"]
WHOLE = ["how many objects are not on the table?", "where is the white cup?", "where is the red thing?"]


def _seen(store, question: str, room) -> dict:
    data = ask(store, question, room=room).to_json()
    return {k: data.get(k) for k in SEEN} | {"templates": data.get("templates")}


@pytest.mark.parametrize("room", ["kitchen", None])
@pytest.mark.parametrize("question", ANCHORED + COLOURED + WHOLE)
def test_an_anchored_read_answers_as_the_whole_room_does(house, store, monkeypatch, question, room):
    from sg3d.queries import compose

    fast = _seen(store, question, room)
    monkeypatch.setattr(compose, "anchor_labels", lambda form, ev: None)     # the whole scope, every edge
    monkeypatch.setattr(compose, "colour_read", lambda form, ev: None)
    whole = _seen(store, question, room)
    assert fast.pop("templates") is not None and whole.pop("templates") is not None
    assert fast == whole
    assert fast["ok"], fast["answer"]


@pytest.mark.parametrize("question", ANCHORED)
def test_a_form_about_anything_held_to_a_named_kind_reads_from_the_anchors(house, store, question):
    templates = ask(store, question, room="kitchen").to_json()["templates"]
    assert "cypher/vqa_scene_linked.cypher" in templates, templates
    assert "cypher/vqa_scene_relations.cypher" not in templates, templates


@pytest.mark.parametrize("question", COLOURED)
def test_a_form_about_anything_of_a_colour_reads_that_colour(house, store, question):
    templates = ask(store, question, room="kitchen").to_json()["templates"]
    assert "cypher/vqa_scene_objects_coloured.cypher" in templates, templates
