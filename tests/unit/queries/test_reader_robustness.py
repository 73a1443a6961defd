"""The reader never fails with a traceback: any text (empty, punctuation, stop words, word salads,
very long, any script) is read into a form or refused with a GrammarError naming where reading
stopped; a bug in a rule's transformer (a StopIteration, an IndexError) is such a refusal too, and
logged; `sg3d.app.ask.ask` turns any other failure of reading or answering into a refusal. No store."""
from __future__ import annotations

import logging
import random

import pytest

from sg3d.queries.reader import grammar
from sg3d.queries.compose import grammar_refusal
from sg3d.queries.reader.reading import GrammarReader
from sg3d.queries.reader.typos import typo_nouns, typo_vocabulary
from sg3d.queries.reader.grammar import RESERVED, GrammarError, ReaderFailure, read
from sg3d.queries.logic import Form
from sg3d.queries.reader.tidy import tidy
from sg3d.queries.reader.typos import fix_typos
from sg3d.queries.vocabulary import MAX_QUESTION


class _NoRooms:
    """A store with no rooms: no name a question says is a room's."""

    def names(self) -> list:
        return []


def reading(question: str):
    """The store-free reader: phrasing, typos, the grammar. A Form, or the GrammarError refusing it."""
    text = tidy(question).text
    text, _ = fix_typos(text, typo_vocabulary(), (), typo_nouns())
    if not text:
        return GrammarError("empty question")
    try:
        return GrammarReader().read(text, _NoRooms())
    except GrammarError as exc:
        return exc


def _salads(n: int, seed: int = 20240611) -> list[str]:
    rng = random.Random(seed)
    words = sorted(typo_vocabulary() | set(RESERVED)) + ["?", ",", ".", "it", "them", "one", "2", "3 m", "not"]
    return [" ".join(rng.choice(words) for _ in range(rng.randint(1, 12))) for _ in range(n)]


ODD = [
    "", " ", "   \t  ", "\n", "?", "?!?", "...", ",,,", "-- -", "'", "''", "\"\"", "()", "[]", "(the big one)",
    "- - -", "/ + &", "...?", "%$#@!", "0", "3.5", "3 m", "-1", "1e9",
    "the", "the the the", "is are the a", "what", "how many", "where is", "it", "them", "the of", "a an the",
    "and or but", "not", "no", "except", "which one", "is it", "how", "where", "how far", "between",
    "is there", "are there no", "the nearest", "closest to", "in the", "on on on on", "next to next to",
    "where can i", "what can i", "i", "i am", "so, correct?", "right?", "isn't it?", "tell me", "please",
    "hey robot", "um, so, well", "quick,", "I can't find it. Where is it?", "it. where is it?",
    "the. where is it?", "a, what colour is it?", "do any of the rooms have", "is there a room with",
    "is the on the white?", "is the book on the white", "what colour's", "'s the", "anything i can",
    "this room has", "would you be so kind as to", "what can i drink it from",
    "où est la tasse ?", "küche", "кухня стол", "台所はどこ", "مطبخ", "🙂🙂🙂", "where is the 🙂?", "ＦＵＬＬ ｗｉｄｔｈ",
    "a\u200bb", "\u0000", "\ufeffwhere is the sink", "where\u00a0is\u00a0the\u00a0sink", "e\u0301",
    "where is the sink " * 25, "how many " + "very " * 200 + "big cups", ("x" * 400),
    " ".join(["chair"] * 120), "is " * 150, "(" * 50 + ")" * 50, "[" * 40,
]


@pytest.mark.parametrize("question", ODD + _salads(200))
def test_any_text_is_read_or_refused_cleanly(question):
    question = question[:MAX_QUESTION]
    got = reading(question)
    assert isinstance(got, (Form, GrammarError)), got
    if isinstance(got, GrammarError):
        text = grammar_refusal(tidy(question).text, got).text
        assert text and "\n" not in text and "Traceback" not in text


def test_a_transformer_that_stops_is_a_refusal_naming_the_word(monkeypatch, caplog):
    def broken(self, items):
        return next(iter(()))           # StopIteration, as a rule edited without its parts would

    monkeypatch.setattr(grammar._ToForm, "where", broken)
    with caplog.at_level(logging.WARNING, logger="sg3d.queries"):
        with pytest.raises(ReaderFailure) as caught:
            read("where is the sink")
    assert caught.value.word == "sink"
    assert grammar_refusal("where is the sink", caught.value).text == "I stopped reading this question at 'sink'"
    assert "StopIteration" in caplog.text


@pytest.mark.parametrize("error", [IndexError("list index out of range"), KeyError("x"), StopIteration()])
def test_any_failure_of_a_transformer_is_a_reader_failure(monkeypatch, error):
    def broken(self, items):
        raise error

    monkeypatch.setattr(grammar._ToForm, "count", broken)
    with pytest.raises(ReaderFailure):
        read("how many cups are there")


def test_a_rule_without_its_part_refuses_instead_of_stopping():
    with pytest.raises(GrammarError, match="stopped"):
        grammar._one(iter(()))


def test_the_grammar_refusals_of_before_keep_their_words():
    with pytest.raises(GrammarError) as caught:
        read("the nearest chair")
    assert caught.value.word == "nearest" and not isinstance(caught.value, ReaderFailure)


class _Store:
    """No store is read before the failure the tests put in."""

    def read(self, name, **params):
        return []

    def reading(self, fn):
        return fn()


def test_ask_refuses_when_reading_fails_with_any_exception(monkeypatch, caplog):
    from sg3d.app import ask as app_ask
    from sg3d.queries import vqa

    def broken(*args, **kwargs):
        raise StopIteration

    monkeypatch.setattr(vqa, "answer", broken)
    with caplog.at_level(logging.WARNING, logger="sg3d.queries"):
        asked = app_ask.ask(_Store(), "where is the sink")
    assert not asked.ok and "\n" not in asked.answer.text and "StopIteration" in asked.answer.text
    assert "StopIteration" in caplog.text


def test_ask_leaves_store_failures_to_the_front_ends(monkeypatch):
    from sg3d.app import ask as app_ask
    from sg3d.graphdb.embedded import StoreLost
    from sg3d.queries import vqa

    def lost(*args, **kwargs):
        raise StoreLost("the store went away")

    monkeypatch.setattr(vqa, "answer", lost)
    with pytest.raises(StoreLost):
        app_ask.ask(_Store(), "where is the sink")


def test_a_failing_rewrite_is_a_refusal_naming_the_first_word(monkeypatch):
    from sg3d.queries import vqa
    from sg3d.queries.reader import tidy as phrasing

    def broken(text):
        raise ValueError("a rewrite went wrong")

    monkeypatch.setattr(phrasing, "tidy", broken)
    a = vqa.answer(_Store(), "where is the sink")
    assert not a.ok and a.text.startswith("I stopped reading this question at 'where'") and "\n" not in a.text


def test_a_question_past_the_limit_is_refused_before_reading():
    from sg3d.queries import vqa

    a = vqa.answer(_Store(), "where is the sink " * 200)
    assert not a.ok and "characters long" in a.text
