"""Compositional questions (sg3d/queries/reader/grammar.py -> sg3d/queries/compose.py) on a real store holding
hand-made rooms merged through the real merge: unnamed objects, structure, second colours,
distances, negation, comparisons, rooms, names printed by `ask` asked back, typos, refusals."""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from sg3d.queries.vqa import answer
from tests.factories import graph, obj


def _o(local_id, label, centre, size, colour="white", layer="object", shape=None, colour2=None, frame=0):
    o = obj(local_id, label, centre, size=size, colour=colour, frame=frame)
    o.box_centre = tuple(centre)
    o.layer, o.shape, o.colour2 = layer, shape, colour2
    return o


@pytest.fixture
def flat(store):
    """kitchen (z up, floor top at 0): a 0.73 m table with 2 cups (one white with red), a pink
    book and an unnamed flat white thing on it; 3 chairs (2 beside the table); a counter holding
    a tv; 'küche' (1 chair) and 'my room' (2 chairs). Returns local id -> stored id."""
    kitchen = graph([
        _o("floor", "floor", (2, 2, -0.01), (4, 4, 0.02), colour="grey", layer="structure"),
        _o("counter", "counter", (3.5, 0.3, 0.45), (1.0, 0.6, 0.9), colour="grey", layer="structure"),
        _o("t", "dining table", (1, 1, 0.365), (1.6, 0.9, 0.73), colour="brown"),
        _o("c1", "chair", (0.2, 1, 0.45), (0.5, 0.5, 0.9), colour="red"),
        _o("c2", "chair", (1.8, 1, 0.45), (0.5, 0.5, 0.9), colour="blue"),
        _o("c3", "chair", (3.8, 3.8, 0.4), (0.4, 0.4, 0.8), colour="red"),
        _o("u1", "cup", (1.0, 1.0, 0.78), (0.1, 0.1, 0.1), colour="white", colour2="red"),
        _o("u2", "cup", (1.3, 0.8, 0.78), (0.1, 0.1, 0.1), colour="red"),
        _o("x1", "object", (0.7, 1.2, 0.74), (0.30, 0.22, 0.02), colour="white", shape="flat"),
        _o("b1", "book", (1.2, 1.3, 0.75), (0.2, 0.15, 0.03), colour="pink"),
        _o("tv", "tv", (3.5, 0.3, 1.1), (0.6, 0.1, 0.4), colour="black"),
    ], relations=[("u1", "ON", "t", 0.9), ("u2", "ON", "t", 0.9), ("x1", "ON", "t", 0.8), ("b1", "ON", "t", 0.9),
                  ("b1", "NEXT_TO", "u1", 0.8), ("c1", "NEXT_TO", "t", 0.8), ("c2", "NEXT_TO", "t", 0.8),
                  ("c1", "ON", "floor", 0.9), ("c2", "ON", "floor", 0.9), ("c3", "ON", "floor", 0.9),
                  ("t", "ON", "floor", 0.9), ("tv", "ON", "counter", 0.9)], room="kitchen", building="home")
    kitchen.up = (0.0, 0.0, 1.0)
    ids = dict(merge_local_graph(store, kitchen).node_ids)
    ids.update(merge_local_graph(store, graph([_o("k1", "chair", (0, 0, 0.45), (0.5, 0.5, 0.9))],
                                              room="küche", building="home")).node_ids)
    ids.update(merge_local_graph(store, graph([_o("m1", "chair", (0, 0, 0.45), (0.5, 0.5, 0.9)),
                                               _o("m2", "chair", (3, 0, 0.45), (0.5, 0.5, 0.9))],
                                              room="my room", building="home")).node_ids)
    store.write("building_adjacent_merge", room_a=room_id("home", "kitchen"), room_b=room_id("home", "küche"),
                shared=1, residual=0.0)
    return ids


def ask(store, q, **kw):
    a = answer(store, q, use_embedding=False, **kw)
    assert a.ok, a.text
    return a


def ids_of(a) -> set:
    return {o["id"] for o in a.objects}


@pytest.mark.parametrize("question, n", [
    ("how many things are on the table?", 4),                 # the unnamed flat object counts too
    ("how many objects are there?", 9),                       # floor and counter are structure
    ("how many chairs are within 1 m of the table?", 2),
    ("how many chairs are not next to the table?", 1),
    ("how many chairs are farther than 2 m from the table?", 1),
    ("how many chairs are between 50 cm and 1 metre from the table?", 2),
    ("how many cups are on the table and next to the pink book?", 1),
    ("how many cups or books are on the table?", 3),
    ("how many red cups are on the table?", 1),
    ("how many walls are there?", 0),
])
def test_counts(store, flat, question, n):
    assert ask(store, question, room="kitchen").value == n


def test_unnamed_objects_are_listed_by_their_look(store, flat):
    a = ask(store, "what is on the table?", room="kitchen")
    assert ids_of(a) == {flat[k] for k in ("u1", "u2", "x1", "b1")}
    assert a.text.startswith("4 things on the dining table") and "white object (flat, about 30x22 cm)" in a.text


def test_structure_answers_what_stands_on_it(store, flat):
    a = ask(store, "what is on the floor?", room="kitchen")
    assert ids_of(a) == {flat[k] for k in ("c1", "c2", "c3", "t")}
    assert ids_of(ask(store, "what is on the counter?", room="kitchen")) == {flat["tv"]}
    biggest = ask(store, "what is the biggest object?", room="kitchen")
    assert biggest.value["id"] == flat["t"]                   # not the floor: structure is not an object


def test_tall_is_the_box_and_high_is_above_the_floor(store, flat):
    assert ask(store, "how tall is the table?", room="kitchen").value == pytest.approx(0.73, abs=0.005)
    assert ask(store, "how high is the table?", room="kitchen").value == pytest.approx(0.73, abs=0.005)
    assert ask(store, "how high is the tv?", room="kitchen").value == pytest.approx(1.3, abs=0.005)
    assert ask(store, "which is the tallest chair?", room="kitchen").value["id"] in {flat["c1"], flat["c2"]}


def test_absence_is_worded_as_absence_of_evidence(store, flat):
    for q in ("is there a keyboard?", "how many keyboards are on the table?", "where is the keyboard?",
              "how many walls are there?", "which cup is closest to the keyboard?", "how many cups are on the shelf?",
              "how many cups are near a keyboard?"):
        a = ask(store, q, room="kitchen")
        assert a.absent_evidence and "I have not found" in a.text and "there is no" not in a.text, q
        assert a.to_json()["absent_evidence"] is True
    assert not ask(store, "how many chairs are next to the tv?", room="kitchen").absent_evidence


def test_a_colour_means_the_main_colour_and_says_so(store, flat):
    a = ask(store, "how many red cups are there?", room="kitchen")
    assert a.value == 1 and "1 more cup has red as a second colour" in a.text


@pytest.mark.parametrize("question, key", [
    ("which chair is farthest from the table?", "c3"),
    ("which chair is closest to the red cup?", "c2"),
    ("what colour is the smallest chair?", "c3"),
])
def test_extremes(store, flat, question, key):
    a = ask(store, question, room="kitchen")
    assert ids_of(a) == {flat[key]}


def test_yes_no_about_one_named_object(store, flat):
    a = ask(store, "is the blue chair next to the table?", room="kitchen")
    assert a.value is True and a.text.startswith("yes")
    a = ask(store, "is the blue chair near the tv?", room="kitchen")
    assert a.value is False and "I have not found" in a.text and not a.absent_evidence


def test_compare_and_more_than(store, flat):
    assert ask(store, "are there more chairs than cups?", room="kitchen").value is True
    assert ask(store, "are there fewer chairs than cups?", room="kitchen").value is False
    assert ask(store, "are there more than 2 chairs?", room="kitchen").value is True


def test_distance_between_two(store, flat):
    a = ask(store, "how far is the pink book from the white cup?", room="kitchen")
    assert a.value == pytest.approx(((0.2 ** 2 + 0.3 ** 2 + 0.03 ** 2) ** 0.5), abs=0.01)


def test_names_printed_by_ask_are_accepted_back(store, flat):
    """Every name a listing prints, asked back, refers to that object."""
    for listing in ("what is on the table?", "list the chairs", "what is on the floor?"):
        a = ask(store, listing, room="kitchen")
        assert a.provenance
        for o in a.provenance:
            back = ask(store, f"where is the {o['name']}?", room="kitchen")
            assert {x["id"] for x in back.provenance} == {o["id"]}, (listing, o["name"], back.text)


def test_typos_are_fixed_and_reported(store, flat):
    a = ask(store, "how many chiars are next to the tabel?", room="kitchen")
    assert a.value == 2 and "read 'chiars' as 'chairs'" in a.text and "read 'tabel' as 'table'" in a.text
    a = ask(store, "could you tell me where the sink is please", room="kitchen")
    assert a.absent_evidence                          # read, and no sink in the kitchen


@pytest.mark.parametrize("question, word", [
    ("how many chairs are within 1.5 of the table?", "1.5"),
    ("how many chairs are closer than the table?", "closer"),
    ("how many chairs are nearer the table than the tv?", "nearer"),
])
def test_refusals_name_the_word_not_read(store, flat, question, word):
    a = answer(store, question, room="kitchen", use_embedding=False)
    assert not a.ok and f"'{word}'" in a.text and len(a.text.splitlines()) == 1


def test_rooms(store, flat):
    assert ask(store, "how many rooms are there?").value == 3
    assert ask(store, "how many chairs are in küche?").value == 1
    assert ask(store, "how many chairs are in my room?").value == 2
    assert {r["room"] for r in ask(store, "which rooms have a chair?").value} == {
        room_id("home", n) for n in ("kitchen", "küche", "my room")}
    assert ask(store, "which room has the most chairs?").value["room"] == room_id("home", "kitchen")
    assert ask(store, "which rooms are next to the kitchen?").value == ["küche"]
    assert ask(store, "which rooms are next to küche?").value == ["kitchen"]
    assert ask(store, "how many rooms are there?", building="home").value == 3
    a = answer(store, "how many chairs are within 1 m of the table?", building="elsewhere")
    assert not a.ok and "no building 'elsewhere'" in a.text


def test_affordances(store, flat):
    assert ids_of(ask(store, "where can I sit?", room="kitchen")) == {flat[k] for k in ("c1", "c2", "c3")}
    assert ids_of(ask(store, "where can I put my cup?", room="kitchen")) == {flat["t"], flat["counter"]}


def test_explain_prints_the_logical_form_and_templates(store, flat):
    from sg3d.commands.ask import ask as ask_cmd

    class Settings:
        def __init__(self, s):
            self._s = s

        def store(self):
            return self._s

        reader = store

    runner = CliRunner()
    r = runner.invoke(ask_cmd, ["how many chairs are within 1 m of the table?", "--room", "kitchen", "--explain"],
                      obj=Settings(store))
    assert r.exit_code == 0, r.output
    assert r.output.splitlines()[0].startswith("2 chairs within 1 m of the dining table")
    assert "logical form:" in r.output and '"within_m": [null, 1.0]' in r.output
    assert "template: cypher/vqa_scene_objects_in_rooms.cypher" in r.output
    r = runner.invoke(ask_cmd, ["is there a keyboard", "--room", "kitchen", "--json"], obj=Settings(store))
    assert json.loads(r.output)["absent_evidence"] is True


@pytest.mark.parametrize("question, same_as", [
    ("Could you tell me how many chairs there are within one and a half metres of the table, please?",
     "how many chairs are within 1.5 m of the table?"),
    ("What's the distance from the pink book to the white mug?", "how far is the pink book from the white cup?"),
    ("Do we have more chairs than cups?", "are there more chairs than cups?"),
    ("Tell me the colour of the smallest chair", "what colour is the smallest chair?"),
    ("What sits on the table next to the white cup?", "what is on the table next to the white cup?"),
    ("Is the pink book lying on the table?", "is the pink book on the table?"),
    ("Is there somewhere I can sit?", "where can I sit?"),
    ("What can you see on the counter?", "what is on the counter?"),
    ("Which mug is the furthest from the tv", "which cup is farthest from the tv?"),
    ("How many rooms do you know?", "how many rooms are there?"),
    ("What is the height of the table?", "how tall is the table?"),
    ("What's the closest chair to the red cup?", "which chair is closest to the red cup?"),
    ("How far apart are the pink book and the white cup?", "how far is the pink book from the white cup?"),
    ("How many mugs sit less than 50cm from a book?", "how many cups are within 0.5 m of the book?"),
    ("Is the number of chairs bigger than the number of cups?", "are there more chairs than cups?"),
    ("Which mug is furthest away from the TV?", "which cup is farthest from the tv?"),
    ("How many rooms does the building have?", "how many rooms are there?"),
    ("Anything on the counter?", "is there anything on the counter?"),
    ("Where exactly is the tv located?", "where is the tv?"),
    ("Where could I sit down?", "where can I sit?"),
    ("Which chair is the closest one to the red mug?", "which chair is closest to the red cup?"),
    ("count the cups that are less than half a metre from a book", "how many cups are within 0.5 m of the book?"),
    ("how many of the chairs are not next to the table?", "how many chairs are not next to the table?"),
    ("the smallest chair, what colour is it?", "what colour is the smallest chair?"),
])
def test_phrasings_read_as_the_plain_question(store, flat, question, same_as):
    a, b = ask(store, question, room="kitchen"), ask(store, same_as, room="kitchen")
    assert (a.form, a.value) == (b.form, b.value), (a.text, b.text)


def test_common_words_are_not_read_as_typos():
    from sg3d.queries.reader.typos import typo_vocabulary
    from sg3d.queries.reader.tidy import tidy
    from sg3d.queries.reader.typos import fix_typos

    text, notes = fix_typos(tidy("how many mugs with a white glaze are there").text, typo_vocabulary())
    assert notes == [] and "with" in text.split()
    text, notes = fix_typos(tidy("how many tabels are there").text, typo_vocabulary())
    assert notes == ["read 'tabels' as 'tables'"]


@pytest.mark.parametrize("text, band", [
    ("how many cups are within 30 cm of the sink", (None, 0.3)),
    ("how many cups are within 300 mm of the sink", (None, 0.3)),
    ("how many cups are closer than 2 ft to the sink", (None, 0.6096)),
    ("how many cups are farther than 1.5 m from the sink", (1.5, None)),
    ("how many cups are more than 2 m away from the sink", (2.0, None)),
    ("how many cups are less than 0.5 m from the sink", (None, 0.5)),
    ("how many cups are between 1 and 2 m from the sink", (1.0, 2.0)),
    ("how many cups are between 50 cm and 1 m from the sink", (0.5, 1.0)),
])
def test_the_grammar_reads_distances_with_units(text, band):
    from sg3d.queries.reader.grammar import read

    form = read(text)
    (f,) = form.filters
    assert f.kind == "distance"
    for got, want in zip((f.low_m, f.high_m), band):
        assert got == (None if want is None else pytest.approx(want))


def test_the_grammar_reads_negation_conjunction_and_nesting():
    from sg3d.queries.reader.grammar import read

    form = read("how many chairs are not near the tv or the sink and next to the table")
    assert form.op == "count" and [f.negated for f in form.filters] == [True, False]
    assert [a.text() for a in form.filters[0].other.alternatives] == ["tv", "sink"]
    form = read("what is on the table next to the pink book")
    (on,) = form.filters
    assert on.relation == "on" and on.other.filters[0].relation == "next to"
    assert read("which cup is farthest from the tv").sets[0].toward.text() == "tv"
    assert read("are there more books than tvs").compare == "more"
