"""The grammar as the question reader (`QuestionReader`, sg3d/queries/reader/__init__.py): plain
text -> the Form it asks, with multi-word room names read as one word each where the grammar
would otherwise stop at 'room'; and the rooms of the store for one question, each looked up once."""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Optional

from sg3d.core.stored import Row
from sg3d.queries.logic import Form
from sg3d.queries.reader import RoomNames
from sg3d.queries.reader.grammar import GrammarError, read
from sg3d.queries.reader.typos import typo_vocabulary


class GrammarReader:
    """The LALR grammar (sg3d/queries/data/question.lark) behind the `QuestionReader` protocol."""

    def read(self, text: str, rooms: RoomNames) -> Form:
        """Normalised text -> Form, retrying with multi-word room names as one word each ("in my
        room", "in the living room": 'room' is a grammar word; `Form.rooms_said` gives each
        name back). GrammarError when neither reads."""
        try:
            return read(text)
        except GrammarError as first:
            if " room" not in f" {text}":
                raise
            out, placeholders = room_placeholders(text, rooms.names())
            if not placeholders:
                raise first
            try:
                form = read(out)
            except GrammarError:
                raise first from None
            return replace(form, rooms_said=placeholders)


class StoredRooms:
    """The rooms of the store for one question, each read once: the names a question may call a
    room by (`names`, read only when a reading needs them) and the rooms a name means (`rows`,
    one indexed look-up per name, whose "read as" notes go to `notes`)."""

    def __init__(self, names: Callable[[], list], named: Callable[[str], list[Row]], notes: list[str]):
        self._names, self._named, self.notes = names, named, notes
        self.seen: dict[str, list[Row]] = {}
        self._all: Optional[list] = None

    def names(self) -> list:
        if self._all is None:
            self._all = self._names()
        return self._all

    def rows(self, name: str) -> list[Row]:
        if name not in self.seen:
            self.seen[name] = self._named(name)
            said = self.seen[name][0].get("read_as") if self.seen[name] else None
            if said and said not in self.notes:
                self.notes.append(said)
        return self.seen[name]


class PlacedRooms:
    """The room look-up of a question whose multi-word room names the reader replaced by one word
    each: a placeholder is looked up as the name said; `said` gives that name back (the rooms
    found in a walk are matched by it, sg3d/queries/walk.py)."""

    def __init__(self, room_rows: Callable[[str], list], placeholders: dict[str, str]):
        self.room_rows, self.placeholders = room_rows, placeholders

    def said(self, name: str) -> str:
        words = name.split()
        return self.placeholders.get(words[-1], name) if words else name

    def __call__(self, name: str) -> list:
        return self.room_rows(self.said(name))


def room_lookup(form: Form, room_rows: Callable[[str], list]) -> Callable[[str], list]:
    """How the rooms a form names are looked up: by the names as said."""
    return PlacedRooms(room_rows, dict(form.rooms_said)) if form.rooms_said else room_rows


def room_placeholders(text: str, stored: list) -> tuple[str, dict[str, str]]:
    """Multi-word room names in `text` replaced by one word each (token -> name as said): the
    stored names as written, then "<words> room" spans that name a stored room loosely
    ("the living room" -> `livingroom`, sg3d/queries/place_names.py)."""
    from sg3d.queries.place_names import match_name

    names = sorted((n.lower() for n in stored), key=len, reverse=True)
    placeholders: dict[str, str] = {}
    out = f" {text} "

    def put(name: str) -> None:
        i = len(placeholders)
        token = "roomname" + "abcdefghijklmnopqrstuvwxyz"[i % 26] * (1 + i // 26)
        placeholders[token] = name
        nonlocal out
        out = out.replace(f" {name} ", f" {token} ")

    for name in names:
        if f" {name} " in out:
            put(name)
    words = out.split()
    for j, w in enumerate(words):
        if w != "room":
            continue
        for i in range(max(0, j - 2), j):       # "living room", "guest bed room"
            span = " ".join(words[i:j + 1])
            if words[i] not in ("the", "a", "my", "this", "in") and match_name(span, names, typo_vocabulary()):
                put(span)
                break
    return out.strip(), placeholders
