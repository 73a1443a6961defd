"""One reader for every question (issue 37): the grammar reads each question once into a logical
form, the planner picks the per-form templates or the set operations, and the word tables are
written once (sg3d/queries/vocabulary.py). No store: the forms and plans are checked as data."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

from sg3d.queries.compose import plan_question
from sg3d.queries.reader.typos import typo_vocabulary
from sg3d.queries.reader.grammar import RESERVED, GrammarError, read
from sg3d.queries.reader.tidy import tidy
from sg3d.queries.reader.typos import fix_typos
from sg3d.queries.vocabulary import ACTIVITIES, AFFORDANCE_VERBS, RELATIONS

QUERIES = Path(__file__).resolve().parents[3] / "sg3d" / "queries"


def form(question: str) -> dict:
    return read(tidy(question).text).form()


def test_no_second_reader_is_left():
    assert not (QUERIES / "parse.py").exists()
    for path in QUERIES.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                assert node.module != "sg3d.queries.parse", path
    # the grammar's relation words are the vocabulary's, all of them
    for phrase in RELATIONS:
        assert all(w in RESERVED for w in phrase.split()), phrase


@pytest.mark.parametrize("question, op", [
    ("what changed in the kitchen?", "changes"), ("what moved since the last scan?", "changes"),
    ("What is gone?", "gone"), ("what disappeared?", "gone"), ("where was the cup before?", "before"),
    ("is there a chair behind the table as seen from the sink?", "exists"),
    ("how many chairs are in front of the table, viewed from the tv", "count"),
    ("which 2 rooms have the fewest objects?", "room_most"), ("what are the 2 rooms with the most chairs?", "room_most"),
    ("which room has the fewest neighbours?", "room_most"), ("in how many rooms is there a chair?", "rooms_counted"),
    ("which room has a sink?", "rooms"), ("in which room is the couch?", "rooms"),
    ("are there exactly 4 chairs?", "at_least"), ("do we have at least 3 chairs?", "at_least"),
    ("is there anything on the counter besides the sink?", "exists"),
    ("how far apart are the two cups?", "distance"), ("is the cup bigger than the book?", "size_compare"),
    ("which one is bigger, the tv or the book?", "size_which"),
    ("I need something to pour water into", "affordance"), ("what can I drink from?", "affordance"),
    ("where can I store things?", "affordance"), ("how many things can I sit on?", "count"),
    ("how many chairs does the kitchen have?", "count"), ("how many chairs the kitchen has", "count"),
    ("the kitchen's chairs", "exists"), ("what are the kitchen's chairs?", "list"),
    ("how many pieces of furniture are there?", "count"), ("which of the bowls is the tiniest", "extreme"),
    ("which is the cup closest to the sink", "extreme"), ("where are all the chairs?", "where"),
    ("how many big bowls are there?", "count"), ("how many mugs have a red pattern?", "count"),
])
def test_every_kind_of_question_is_read_by_the_grammar(question, op):
    assert form(question)["op"] == op


def test_viewpoint_change_and_exception_parts_are_in_the_form():
    f = read(tidy("is there a chair behind the table as seen from the sink?").text)
    assert f.seen_from is not None and f.seen_from.text() == "sink"
    assert form("is there anything on the table other than the cups?")["filters"][0]["filter"] == "except"
    assert form("is there anything on the table that is not a cup?")["filters"][0]["filter"] == "except"
    assert form("are there exactly four chairs?")["compare"] == "exactly"
    assert form("what changed in the kitchen?")["filters"][0]["of"] == {"noun": "kitchen"}
    assert form("how many pieces of furniture for sitting are there?")["sets"][0]["for"] == "sitting"
    assert form("how many mugs with a white glaze are there")["sets"][0]["ignored"] == ["glaze"]
    assert form("which 2 rooms have the fewest objects?")["number"] == 2


def test_simple_questions_are_planned_for_the_per_form_templates():
    q = plan_question("how many red chairs are next to the table?", use_embedding=False)
    assert (q.form, q.target.labels, q.colour, q.relation, q.anchor_target().labels) == \
        ("count", ["chair"], "red", "NEXT_TO", ["dining table"])
    q = plan_question("which chairs are next to a table?", use_embedding=False)
    assert q.anchor_article == "a"
    q = plan_question("is there a chair in front of the table?", use_embedding=False)
    assert q.relation == "IN_FRONT_OF"
    assert plan_question("where is the cup?", use_embedding=False).one
    assert not plan_question("where is a cup?", use_embedding=False).one
    assert plan_question("which is the cup closest to the sink", use_embedding=False).superlative == "closest"


@pytest.mark.parametrize("question, word", [
    ("how many chairs are within 1.5 of the table?", "1.5"),
    ("how many chairs are closer than the table?", "closer"),
    ("what is the weather like?", "weather"),      # it stops at "like", a word it knows
])
def test_a_question_the_grammar_cannot_read_names_the_word(question, word):
    with pytest.raises(GrammarError) as exc:
        read(tidy(question).text)
    from sg3d.queries.compose import grammar_refusal

    assert f"'{word}'" in grammar_refusal(tidy(question).text, exc.value).text


def test_one_affordance_table_covers_the_activities_and_the_shape_named_furniture():
    assert set(ACTIVITIES) == {"sit", "drink", "put things down", "store things", "work", "keep things cold"}
    assert {"chair", "couch", "sofa", "bench", "stool", "bed"} <= set(ACTIVITIES["sit"])
    assert {"cup", "mug", "glass", "bottle"} <= set(ACTIVITIES["drink"])
    assert {"desk", "counter", "shelf", "cabinet", "sideboard"} <= set(ACTIVITIES["put things down"])
    assert ACTIVITIES["keep things cold"] == ["refrigerator"]
    assert {"cabinet", "shelf", "drawer", "sideboard", "refrigerator"} <= set(ACTIVITIES["store things"])
    assert {"desk"} <= set(ACTIVITIES["work"])
    assert set(AFFORDANCE_VERBS.values()) == set(ACTIVITIES)


@pytest.mark.parametrize("question", [
    "how many pieces of furniture for sitting are there?", "where can someone take a seat?",
    "is there anything on the counter besides the sink?", "how many things can I sit on?",
    "which room has the fewest neighbours?", "I need something to pour water into",
])
def test_correctly_spelled_words_are_never_fixed(question):
    text, notes = fix_typos(tidy(question).text, typo_vocabulary())
    assert notes == [] and text == tidy(question).text


@pytest.mark.parametrize("question, word", [
    ("blorp the frobnicator", "blorp"),          # the reader stops at 'the', a word it knows
    ("what is the meaning of life", "meaning"),  # ... at 'of'
    ("how many chairs are there frobbed", "frobbed"),
])
def test_a_refusal_names_the_word_it_could_not_read_not_a_word_it_knows(question, word):
    from sg3d.queries.compose import grammar_refusal

    with pytest.raises(GrammarError) as stopped:
        read(tidy(question).text)
    assert f"'{word}'" in grammar_refusal(tidy(question).text, stopped.value).text
