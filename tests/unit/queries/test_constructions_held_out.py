"""General constructions a held-out set found refused (issue 37, round three), each in several
phrasings with other nouns than the set's; as logical forms (no store). Store-backed answers:
tests/e2e/test_ask_typos_rooms_and_comparisons.py."""
from __future__ import annotations

import pytest

from sg3d.queries.reader.typos import typo_vocabulary
from sg3d.queries.reader.grammar import GrammarError, read
from sg3d.queries.reader.tidy import asked_unit, said_word, tidy
from sg3d.queries.reader.typos import fix_typos
from sg3d.queries.sets import activity
from sg3d.queries.vqa import own_words


def form(question: str) -> dict:
    text, _ = fix_typos(tidy(question).text, typo_vocabulary())
    return read(text).form()


# -- 1. the exception said first; refusals name the words typed ------------------------------------
@pytest.mark.parametrize("question, op, relation, left_out", [
    ("apart from the lamp, what is on the desk?", "list", "on", "lamp"),
    ("other than the kettle, what's near the sink?", "list", "near", "kettle"),
    ("aside from the mugs, how many things are on the shelf?", "count", "on", "mugs"),
    ("besides the bowl, is there anything in the cabinet?", "exists", "in", "bowl"),
])
def test_fronted_exception(question, op, relation, left_out):
    f = form(question)
    assert f["op"] == op
    kinds = {x["filter"]: x for x in f["filters"] + (f.get("sets") or [{}])[0].get("filters", [])}
    assert kinds["rel"]["relation"] == relation and kinds["except"]["of"] == {"noun": left_out}


@pytest.mark.parametrize("question, rewritten, typed", [
    ("apart from the lamp, frobnicate the desk", "except", "apart from"),
    ("other than mugs, which ones glow", "except", "other than"),
    ("what's zorbing the tv", "is", "what's"),
    ("waht zorbles on the shelf", "what", "waht"),
])
def test_a_rewritten_word_is_named_as_typed(question, rewritten, typed):
    text, _ = fix_typos(tidy(question).text, typo_vocabulary())
    assert said_word(question, text, rewritten) == typed
    refusal = own_words(question, text, f"I could not read '{rewritten}' in this question; try e.g. \"x 'except' y\"")
    assert refusal.startswith(f"I could not read '{typed}'") and refusal.endswith("\"x 'except' y\"")


def test_a_typed_word_is_left_as_it_is():
    q = "I don't know what things afford 'juggle'"
    assert own_words("where should i juggle", "where should i juggle", q) == q


# -- 2. possession and existence openers -------------------------------------------------------------
@pytest.mark.parametrize("question, noun", [
    ("do we have a kettle?", "kettle"), ("got a stool in here?", "stool"), ("have we got any plates?", "plates"),
    ("is there any lamp around here?", "lamp"), ("do i have a desk", "desk"), ("have you got a sofa?", "sofa"),
])
def test_having_and_there_being(question, noun):
    f = form(question)
    assert f["op"] == "exists" and f["sets"][0]["noun"] == noun


# -- 3. distances in many shapes ------------------------------------------------------------------
@pytest.mark.parametrize("question, first, second", [
    ("distance from the lamp to the nearest sofa?", "lamp", "sofa"),
    ("how far apart are the fridge and the closest stool?", "fridge", "stool"),
    ("what's the gap between the bed and the wardrobe?", None, None),
    ("how many meters between the oven and the bin?", None, None),
    ("the separation between the desk and the door", None, None),
    ("how many cm is it between the kettle and the toaster", None, None),
])
def test_distance_shapes(question, first, second):
    f = form(question)
    assert f["op"] == "distance"
    if first:
        a, b = f["sets"]
        assert a["noun"] == first and b["noun"] == second and b["from"] == {"noun": first}


def test_the_unit_of_how_many_between_is_the_answer_unit():
    assert asked_unit("how many centimetres between the cup and the kettle?") == "cm"
    assert asked_unit("how many feet is it between the bed and the door") == "ft"


def test_nearest_alone_is_refused_naming_it():
    with pytest.raises(GrammarError) as exc:
        form("what is the nearest lamp")
    assert exc.value.word == "nearest"


# -- 4. polite frames ---------------------------------------------------------------------------------
@pytest.mark.parametrize("question, op", [
    ("would you mind telling me how many stools there are?", "count"),
    ("do you know where the kettle is?", "where"),
    ("can you tell me what is on the shelf?", "list"),
    ("I was wondering how many lamps there are", "count"),
    ("i was wondering if there is a sofa", "exists"),
    ("do you happen to know what colour the bed is?", "attribute"),
])
def test_polite_frames(question, op):
    assert form(question)["op"] == op


# -- 5. positions of every one of a kind --------------------------------------------------------------
@pytest.mark.parametrize("question, noun", [
    ("show me where each stool is", "stool"), ("where is every lamp", "lamp"), ("where's each bottle?", "bottle"),
])
def test_where_each(question, noun):
    f = form(question)
    assert f["op"] == "where" and f["sets"][0]["noun"] == noun


# -- 6. the relation word stranded at the end ----------------------------------------------------------
@pytest.mark.parametrize("question, noun, relation", [
    ("what is the lamp next to?", "lamp", "next to"), ("what is the kettle on?", "kettle", "on"),
    ("what's the rug under?", "rug", "under"), ("what are the books in?", "books", "in"),
])
def test_stranded_relation(question, noun, relation):
    f = form(question)
    assert f["op"] == "list" and not f.get("sets")
    (flt,) = f["filters"]
    assert flt["relation"] == relation and flt["reverse"] is True and flt["of"]["noun"] == noun


# -- 7. which of two is bigger -------------------------------------------------------------------
@pytest.mark.parametrize("question", [
    "which one's bigger: the lamp or the kettle?", "which is smaller, the bed or the stool",
    "which of the sofa and the desk is larger", "which one is larger, the bin or the oven?",
])
def test_which_of_two_is_bigger(question):
    f = form(question)
    assert f["op"] == "size_which" and len(f["sets"]) == 2


# -- 8. typos of question words -------------------------------------------------------------------------
@pytest.mark.parametrize("question, fixed", [
    ("wher is the lamp", "where"), ("hw many stools", "how"), ("waht is on the desk", "what"),
    ("whcih lamp is the tallest", "which"), ("hwo many plates", "how"), ("how mny bowls", "many"),
])
def test_typos_of_question_words(question, fixed):
    tidied = tidy(question)     # a first question word is read before the frames, the rest after
    text, notes = fix_typos(tidied.text, typo_vocabulary())
    assert fixed in text.split() and len(tidied.notes + notes) == 1
    read(text)


@pytest.mark.parametrize("text", ["what is on the desk", "where is the lamp", "how many were there", "who is here"])
def test_correct_question_words_are_never_changed(text):
    assert fix_typos(text, typo_vocabulary()) == (text, [])


# -- 9. could / should / can I in affordances ------------------------------------------------------------
@pytest.mark.parametrize("question, verb, kind", [
    ("which desk could I work at?", "work at", "desk"),
    ("where should I put my books away?", "put books away", None),
    ("where can I sit down?", "sit down", None),
    ("which chair should i sit on", "sit", "chair"),
    ("what might i drink from", "drink", None),
])
def test_modal_affordances(question, verb, kind):
    f = form(question)
    assert f["op"] == "affordance" and f["verb"] == verb
    assert [s["noun"] for s in f["sets"]] == ([kind] if kind else [])


def test_putting_away_is_storing():
    assert activity("put books away") == "store things" and activity("put away") == "store things"


# -- 10. where in the building -----------------------------------------------------------------------------
@pytest.mark.parametrize("question, noun, place", [
    ("where in the house is there a tv?", "tv", "house"),
    ("where in the flat is the kettle", "kettle", "flat"),
    ("where in the kitchen are the mugs?", "mugs", "kitchen"),
])
def test_where_in_a_place(question, noun, place):
    f = form(question)
    assert f["op"] == "where" and f["sets"][0]["noun"] == noun
    assert f["filters"][-1]["relation"] == "in" and f["filters"][-1]["of"]["noun"] == place


def test_away_is_one_word_not_a_way():
    assert form("where could i put the plates away")["verb"] == "put plates away"
