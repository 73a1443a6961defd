"""The grammar behind the QuestionReader protocol: a question's plain text -> the Form it asks,
the store's room names read only when a multi-word room name must be read as one word."""
from __future__ import annotations

import dataclasses

import pytest

from sg3d.queries.logic import OPS, Form
from sg3d.queries.reader import QuestionReader
from sg3d.queries.reader.grammar import GrammarError
from sg3d.queries.reader.reading import GrammarReader, StoredRooms


class _Rooms:
    def __init__(self, names: list[str]):
        self.said, self.asked = names, 0

    def names(self) -> list[str]:
        self.asked += 1
        return self.said


def test_a_question_without_a_room_name_reads_no_room_names():
    rooms = _Rooms(["my room"])
    reader: QuestionReader = GrammarReader()
    form = reader.read("how many chairs are in the kitchen", rooms)
    assert (form.op, form.rooms_said, rooms.asked) == ("count", {}, 0)


def test_a_multi_word_room_name_is_read_as_one_word_and_said_back():
    form = GrammarReader().read("how many chairs are in my room", _Rooms(["my room"]))
    assert form.op == "count" and form.rooms_said == {"roomnamea": "my room"}
    with pytest.raises(GrammarError):
        GrammarReader().read("how many chairs are in my room", _Rooms([]))


def test_a_form_is_never_changed_once_read_and_its_op_is_one_of_the_ops():
    form = GrammarReader().read("show me the biggest bowl", _Rooms([]))
    assert form.op in OPS
    with pytest.raises(dataclasses.FrozenInstanceError):
        form.op = "extreme"
    assert isinstance(form, Form)


def test_the_rooms_of_a_question_are_each_looked_up_once():
    looked: list[str] = []
    notes: list[str] = []

    def named(name: str) -> list[dict]:
        looked.append(name)
        return [{"id": "r1", "read_as": "read 'kitchn' as 'kitchen'"}]

    rooms = StoredRooms(lambda: ["kitchen"], named, notes)
    assert rooms.rows("kitchn") == rooms.rows("kitchn") and looked == ["kitchn"]
    assert rooms.names() == rooms.names() == ["kitchen"] and notes == ["read 'kitchn' as 'kitchen'"]
