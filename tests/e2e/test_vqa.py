"""`sg3d ask` against a real embedded store holding hand-made rooms (the truth is known)."""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from sg3d.queries.compose import plan_question
from sg3d.queries.reader.grammar import GrammarError
from sg3d.queries.sets import Unanswerable
from sg3d.queries.vqa import answer
from tests.scenes import BOWL_JPEG, StoreSettings


def ask(store, q, **kw):
    a = answer(store, q, **kw)
    assert a.ok, a.text
    return a


@pytest.mark.parametrize("question, n", [
    ("how many cups are there?", 2),
    ("How many mugs?", 2),
    ("how many chairs", 4),
    ("how many sofas are there", 2),
    ("how many monitors are in the environment?", 2),
    ("How many pieces of furniture are there?", 7),
    ("how many pieces of cutlery are there?", 3),
    ("how many electronics", 2),
    ("how many red chairs?", 3),
    ("how many red chairs are in the kitchen?", 2),
    ("how many red objects are there", 4),
    ("how many big bowls are there?", 1),
    ("how many small bowls", 1),
    ("how many objects are on the table?", 4),
    ("how many cups are on the dining table?", 2),
    ("how many red cups are on the table", 1),
    ("how many objects are in the sink", 1),
    ("how many things are next to the sink?", 1),
    ("how many things are near the sink?", 1),           # next to is the closer form of near
    ("how many objects are around the sink", 1),
    ("how many toasters are there?", 0),
])
def test_counting(store, house, question, n):
    assert ask(store, question).value == n


def test_hierarchy_breakdown_and_scope(store, house):
    a = ask(store, "how many pieces of furniture are there?", room="kitchen")
    assert a.value == 5
    assert {o["label"]: o["n"] for o in a.objects} == {"chair": 3, "dining table": 1, "couch": 1}
    assert ask(store, "how many furniture", building="home").value == 7
    assert ask(store, "how many chairs are in the living room").value == 1


def test_existence(store, house):
    assert ask(store, "is there a sink?").value is True
    assert ask(store, "is there a toaster?").value is False
    assert ask(store, "are there any sofas in the living room?").value is True
    assert ask(store, "is there a fork on the table?").value is True


def test_listing_and_relations(store, house):
    a = ask(store, "what is on the table?")
    assert sorted(o["id"] for o in a.value) == sorted(house[k] for k in ("u1", "u2", "b1", "f1"))
    a = ask(store, "what is next to the sink?")   # stored bowl -> sink, asked from either side
    assert [o["id"] for o in a.value] == [house["b2"]]
    a = ask(store, "list the chairs", room="kitchen")
    assert sorted(o["id"] for o in a.value) == sorted(house[k] for k in ("c1", "c2", "c3"))


def test_attribute_lookup(store, house):
    assert ask(store, "what colour is the couch?", room="kitchen").value == "grey"
    assert sorted(ask(store, "what color are the sofas?").value) == ["black", "grey"]
    assert ask(store, "how big is the table?").value.startswith("1.50x0.80x0.70")


def test_superlatives_return_the_object_and_its_thumbnail(store, house):
    a = ask(store, "show me the biggest bowl")
    assert a.value["id"] == house["b2"] and a.thumbnail == BOWL_JPEG
    assert ask(store, "show me the smallest bowl").value["id"] == house["b3"]
    # sink at (9, 0.9, 9.6): the white cup is 11.00 m from it, the red one 11.35 m
    assert ask(store, "which is the cup closest to the sink").value["id"] == house["u1"]
    assert ask(store, "show me the bowl closest to the sink").value["id"] == house["b2"]


@pytest.mark.parametrize("question", [
    "what is the weather like?", "how many unicorns are there?", "how many cups are in the garage?",
    "", "show me the biggest spaceship",
])
def test_refusals_are_helpful_and_never_numbers(store, house, question):
    a = answer(store, question)
    assert not a.ok and a.value is None
    # one short line: what was not understood and one example close to the question
    assert "\n" not in a.text and len(a.text) < 200
    assert "try e.g." in a.text or "no room" in a.text


def _nodes(store):
    return store.run_raw("MATCH (n) RETURN count(n) AS n")[1][0][0]


@pytest.mark.parametrize("question", [
    'how many chairs"}) DETACH DELETE n //',
    "MATCH (n) DETACH DELETE n",
    "how many chairs are in the kitchen' OR 1=1 //",
    "what colour is the couch}) MATCH (n) DETACH DELETE n RETURN 1 //",
])
def test_injection_changes_nothing(store, house, question):
    answer(store, "how many chairs")          # the taxonomy (the one write) is already loaded
    before = _nodes(store)
    a = answer(store, question)
    assert _nodes(store) == before
    # never read as a question with the Cypher in it: one refusal line, no value
    assert not a.ok and a.value is None and "\n" not in a.text
    assert "try e.g." in a.text or "no room 'kitchen or 1 1" in a.text


def test_parser_plurals_and_multiword():
    assert plan_question("how many knives", use_embedding=False).target.labels == ["knife"]
    assert plan_question("how many wine glasses", use_embedding=False).target.labels == ["wine glass"]
    assert plan_question("how many benches", use_embedding=False).target.labels == ["bench"]
    assert plan_question("how many cell phones", use_embedding=False).target.labels == ["cell phone"]
    assert plan_question("how many teddy bears", use_embedding=False).target.labels == ["teddy bear"]
    assert plan_question("how many glasses", use_embedding=False).target.labels == ["cup", "wine glass"]
    assert plan_question("how many fridges", use_embedding=False).target.labels == ["refrigerator"]
    # a household noun no category covers is read (it counts 0), a non-word is not
    wardrobes = plan_question("how many wardrobes", use_embedding=False).target
    assert wardrobes.labels == [] and wardrobes.how == "unknown"
    # furniture sg3d names from its shape is a word of its own, not a dining table
    assert plan_question("how many desks", use_embedding=False).target.labels == ["desk"]
    assert plan_question("how many cupboards", use_embedding=False).target.labels == ["cabinet"]
    with pytest.raises((GrammarError, Unanswerable)):
        plan_question("how many florps", use_embedding=False)


def test_cli_answers_explains_writes_thumbnail_and_refuses(store, house, tmp_path):
    from sg3d.commands.ask import ask as ask_cmd

    runner = CliRunner()
    r = runner.invoke(ask_cmd, ["how many red chairs", "--room", "kitchen", "--explain"], obj=StoreSettings(store))
    assert r.exit_code == 0, r.output
    assert r.output.splitlines()[0].startswith("2 red chairs")
    assert "cypher/vqa_objects_in_rooms.cypher" in r.stdout and '"colour": "red"' in r.stdout   # asked for: a result
    assert r.stderr == ""
    no_picture = tmp_path / "chairs.png"
    r = runner.invoke(ask_cmd, ["how many red chairs", "--room", "kitchen", "--out", str(no_picture)],
                      obj=StoreSettings(store))
    assert r.exit_code == 2 and not no_picture.exists(), r.output      # --out that writes nothing is refused
    assert r.stdout.startswith("2 red chairs") and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "no picture" in r.stderr and str(no_picture) in r.stderr
    import cv2

    for name, magic in (("bowl.png", b"\x89PNG"), ("bowl.jpg", b"\xff\xd8"), ("bowl.JPEG", b"\xff\xd8")):
        out = tmp_path / name
        r = runner.invoke(ask_cmd, ["show me the biggest bowl", "--out", str(out), "--json"], obj=StoreSettings(store))
        assert r.exit_code == 0, r.output
        assert out.read_bytes().startswith(magic), name      # the format the extension names
        assert max(cv2.imread(str(out)).shape[:2]) >= 256     # upscaled from 49 px to be visible
        assert json.loads(r.output)["thumbnail"] == str(out)
    r = runner.invoke(ask_cmd, ["show me the biggest bowl", "--out", str(tmp_path / "bowl.gif")], obj=StoreSettings(store))
    assert r.exit_code == 2 and ".png" in r.output
    r = runner.invoke(ask_cmd, ["what is the meaning of life"], obj=StoreSettings(store))
    assert r.exit_code != 0 and "try e.g." in r.output and len(r.output.strip().splitlines()) == 1


def test_parenthetical_remarks_are_dropped(store, house):
    assert ask(store, "how many cups (mugs included) are there?").value == 2
    assert ask(store, "how many red chairs [roughly] are in the kitchen (not the hall)?").value == 2


def test_or_and_slash_name_one_or_two_categories(store, house):
    assert plan_question("how many cups or mugs", use_embedding=False).target.labels == ["cup"]
    assert plan_question("how many sofas / couches", use_embedding=False).target.labels == ["couch"]
    a = ask(store, "how many cups or bowls are there?")
    assert a.value == 5 and "counted together" in a.text and "cup" in a.text and "bowl" in a.text
    a = ask(store, "how many forks/knives are there?")
    assert a.value == 2 and "counted together" in a.text


def test_known_word_with_unknown_words_is_not_guessed(store, house):
    # a known group after modifiers: the group
    assert plan_question("how many pieces of dining furniture", use_embedding=False).target.names == ["furniture"]
    assert plan_question("how many wooden chairs", use_embedding=False).target.labels == ["chair"]
    # a known noun after other known nouns: refused, never read whole by the embedding
    q = "how many dining furniture tables chairs are there"
    with pytest.raises((GrammarError, Unanswerable)):
        plan_question(q)
    a = answer(store, q)
    assert not a.ok and a.value is None
    # a compound household noun is its own thing, not its head noun: none are stored
    a = ask(store, "how many table lamps are there")
    assert a.value == 0 and a.query.target.labels == []


def test_superlative_with_a_relation_stays_among_the_related(store, house):
    a = ask(store, "which is the largest object on the table?")
    assert a.value["id"] in {house[k] for k in ("u1", "u2", "b1", "f1")}
    assert a.value["id"] == house["b1"]            # 0.2x0.2x0.1 beats the 0.1 cubes
    a = ask(store, "show me the biggest cup on the table")
    assert a.value["id"] == house["u2"] and "on the dining table" in a.text   # 0.12 m cube beats 0.1 m
    a = answer(store, "show me the smallest bowl next to the tv")
    assert a.value is None and "I have not found a bowl next to the tv" in a.text


def test_where_is_names_relations_and_room(store, house):
    a = ask(store, "where is the knife?")
    assert a.form == "where" and a.value[0]["id"] == house["k1"]
    assert a.value[0]["relations"] == [{"rel": "IN", "other_id": house["sk"], "other_label": "sink"}]
    assert "the knife is in the sink, in the kitchen" in a.text   # names as everywhere (sg3d/queries/naming.py)
    a = ask(store, "where is the sink?")          # the bowl is stored NEXT_TO the sink: symmetric
    assert {(x["rel"], x["other_id"]) for x in a.value[0]["relations"]} == {("NEXT_TO", house["b2"])}
    a = ask(store, "where are the tvs?")
    assert {o["room"] for o in a.value} == {"home/kitchen", "home/living room"}
    a = answer(store, "where is the toaster?")     # an answer (there is none), not a refusal
    assert a.value == [] and "I have not found a toaster" in a.text and a.absent_evidence
