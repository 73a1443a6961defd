"""Questions over the rooms found in a walk (sg3d/queries/walk.py), without a store: how they are
read, how a room is named (its name, else its guessed kind), the way between rooms, and what
sg3d cannot see (a window) never said to be absent."""
from __future__ import annotations

import pytest

from sg3d.app.places import guess_kind
from sg3d.queries.reader.grammar import GrammarError, read
from sg3d.queries.reader.tidy import tidy
from sg3d.queries.walk import named, not_detected, room_words, shortest_way


def form(question: str) -> dict:
    return read(tidy(question).text).form()


@pytest.mark.parametrize("question, op, nouns", [
    ("what is in the room next to the kitchen?", "rooms_next_hold", ["kitchen"]),
    ("What's in the rooms adjacent to the bedroom", "rooms_next_hold", ["bedroom"]),
    ("what do the rooms next to the office hold?", "rooms_next_hold", ["office"]),
    ("what rooms are next to the kitchen?", "rooms_next_to", ["kitchen"]),
    ("how do I get from the kitchen to the bedroom?", "route", ["kitchen", "bedroom"]),
    ("how can we walk from the office to the kitchen", "route", ["office", "kitchen"]),
    ("how do I get to the bedroom from the kitchen?", "route", ["kitchen", "bedroom"]),
    ("which rooms don't have a window?", "rooms", []),
    ("which room is the fridge in?", "rooms", ["fridge"]),
])
def test_walk_questions_are_read(question, op, nouns):
    f = form(question)
    assert f["op"] == op
    assert [s["noun"] for s in f["sets"]] == nouns


def test_which_rooms_have_no_window_is_read_as_rooms_lacking():
    assert form("which rooms have no window?") == {"op": "rooms", "sets": [], "lacking": [{"noun": "window"}]}


def test_in_the_room_alone_is_still_the_scope():
    assert form("what is in the room?") == {"op": "list", "sets": []}


def test_a_way_asked_with_another_verb_is_refused_naming_it():
    with pytest.raises(GrammarError) as e:
        form("how do I fly from the kitchen to the bedroom?")
    assert e.value.word == "fly"


def _room(i: int, kind=None, evidence=(), x=0.0, doors=()):
    return {"id": f"w#{i}", "name": f"room {i}", "walk": "home/w", "kind_guess": kind, "kind_evidence": list(evidence),
            "x": x, "y": 0.0, "z": 0.0, "objects": [],
            "doorways": [{"doorway": d, "room": r, "width": 0.9, "x": dx, "y": 0.0, "z": 0.0} for d, r, dx in doors]}


LAYER = [
    _room(1, "kitchen", ["refrigerator", "sink"], 0.0, [("d1", "w#2", 2.0)]),
    _room(2, None, (), 4.0, [("d1", "w#1", 2.0), ("d2", "w#3", 6.0), ("d3", "w#4", 4.5)]),
    _room(3, "bedroom", ["bed"], 8.0, [("d2", "w#2", 6.0), ("d4", "w#4", 8.0)]),
    _room(4, "office", ["desk", "monitor"], 8.0, [("d3", "w#2", 4.5), ("d4", "w#3", 8.0)]),
]


def test_a_room_is_named_by_its_name_before_its_guessed_kind():
    assert named(LAYER, "room 3") == ([LAYER[2]], False)
    assert named(LAYER, "Room 3") == ([LAYER[2]], False)
    assert named(LAYER, "kitchen") == ([LAYER[0]], True)
    assert named(LAYER, "the bed room".removeprefix("the ")) == ([LAYER[2]], True)
    assert named(LAYER, "bathroom") == ([], False)
    renamed = [dict(LAYER[1], name="kitchen")] + LAYER[2:] + [LAYER[0]]
    assert named(renamed, "kitchen") == ([renamed[0]], False)     # a user's name wins over a guess


def test_a_guess_is_said_as_a_guess_with_its_evidence():
    assert room_words(LAYER[0]) == "room 1 (looks like a kitchen: refrigerator, sink)"
    assert room_words(LAYER[0], guessed=True) == "room 1 (the kitchen by a guess from what it holds: refrigerator, sink)"
    assert room_words(LAYER[1], guessed=True) == "room 2"


def test_the_way_is_the_shortest_walk_over_rooms_and_doorways():
    metres, path = shortest_way(LAYER, [LAYER[0]], [LAYER[2]])
    assert path == ["w#1", "d1", "w#2", "d2", "w#3"]
    assert metres == pytest.approx(2 + 2 + 2 + 2)
    # two doorways lead on from room 2: the shorter one (d3 to room 4, 0.5 + 3.5 m) is taken
    assert shortest_way(LAYER, [LAYER[0]], [LAYER[3]])[1] == ["w#1", "d1", "w#2", "d3", "w#4"]
    alone = [_room(5)]
    assert shortest_way(LAYER + alone, [LAYER[0]], alone) is None


def test_a_kind_no_label_covers_is_not_detected():
    class R:
        def __init__(self, kind, words):
            self.kind, self.np = kind, type("NP", (), {"text": lambda self: words})()

    assert not_detected([R("named", "fridge"), R("unknown", "window")]) == "window"
    assert not_detected([R("named", "fridge")]) is None


@pytest.mark.parametrize("labels, kind", [
    (["sink", "refrigerator", "cup"], "kitchen"), (["bed", "book"], "bedroom"), (["desk", "monitor"], "office"),
    (["couch", "tv"], "living room"), (["cup", "book"], None),
])
def test_a_kind_is_guessed_from_what_a_room_holds(labels, kind):
    assert guess_kind(labels)[0] == kind


def _windowed(i: int, windows: int, unseen: float) -> dict:
    return {"id": f"w#{i}", "name": f"room {i}", "walk": "home/w", "kind_guess": None, "kind_evidence": [],
            "unseen_outline": unseen, "windows": [{"id": f"win{i}.{k}", "size": [1.0, 0.05, 1.1]} for k in range(windows)]}


def test_rooms_without_a_window_are_named_and_an_unseen_outline_says_no_window_seen():
    from sg3d.queries.walk import UNSEEN_OUTLINE_SHARE, windows_answer

    rows = [_windowed(1, 1, 0.0), _windowed(2, 0, 0.0), _windowed(3, 0, UNSEEN_OUTLINE_SHARE - 0.01),
            _windowed(4, 0, UNSEEN_OUTLINE_SHARE)]
    text, value = windows_answer(rows, lacking=True)
    assert text.startswith("room 2, room 3; no window in them; no window seen in room 4 ("), text
    assert [(v["room"], v["seen"]) for v in value] == [("room 2", True), ("room 3", True), ("room 4", False)]
    text, value = windows_answer(rows, lacking=False)
    assert text == "room 1 (1 window: 1.0 m wide, 1.1 m tall)"
    assert value == [{"room": "room 1", "walk": "home/w", "windows": ["win1.0"]}]
    assert windows_answer([_windowed(1, 2, 0.0)], lacking=True)[0] == "none: every room has a window"
    assert windows_answer([_windowed(1, 0, 0.0)], lacking=False)[0].startswith("none: no window was found")
