"""The question reader: people's phrasing -> the plain text the grammar reads (`tidy`, over the
rule table sg3d/queries/data/rephrase_rules.toml), typos (`typos`), and the grammar that reads
the text into a logical form."""
from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from sg3d.queries.logic import Form


class RoomNames(Protocol):
    """The rooms of the store a question may name, looked up once for the question."""

    def names(self) -> list: ...


class QuestionReader(Protocol):
    """Reads a question's plain text (people's phrasing undone by `tidy.tidy`) into what it asks.
    GrammarError (sg3d/queries/reader/grammar.py) when it cannot, naming where it stopped."""

    def read(self, text: str, rooms: RoomNames) -> Form: ...
