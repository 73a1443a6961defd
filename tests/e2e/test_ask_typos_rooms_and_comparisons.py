"""Questions, round two, on a real store: typos only for unknown words, room names matched like
object names, and the new phrasings (distance, size comparison, rooms counted, at least, colour
sets, polite wrappers, 'take a seat', 'next to a cup'). Every expected value is computed from
the stored graph in the test."""
from __future__ import annotations

import math

import pytest

from sg3d.graphdb.merge import merge_local_graph
from sg3d.queries.vqa import answer
from tests.factories import graph, obj


def _o(local_id, label, centre, size, colour="white", layer="object"):
    o = obj(local_id, label, centre, size=size, colour=colour)
    o.box_centre = tuple(centre)
    o.layer = layer
    return o


@pytest.fixture
def home(store):
    """'kitchen': a table with 2 cups (red, white) and a white book, 3 chairs, a black tv;
    'livingroom': a couch, a red chair and a tv (building 'home')."""
    kitchen = graph([
        _o("floor", "floor", (2, 2, -0.01), (4, 4, 0.02), colour="grey", layer="structure"),
        _o("t", "dining table", (1, 1, 0.365), (1.6, 0.9, 0.73), colour="brown"),
        _o("c1", "chair", (0.2, 1, 0.45), (0.5, 0.5, 0.9), colour="red"),
        _o("c2", "chair", (1.8, 1, 0.45), (0.5, 0.5, 0.9), colour="blue"),
        _o("c3", "chair", (3.8, 3.8, 0.4), (0.4, 0.4, 0.8), colour="white"),
        _o("u1", "cup", (1.0, 1.0, 0.78), (0.1, 0.1, 0.1), colour="white"),
        _o("u2", "cup", (1.3, 0.8, 0.78), (0.08, 0.08, 0.12), colour="red"),
        _o("b1", "book", (1.2, 1.3, 0.75), (0.2, 0.15, 0.03), colour="white"),
        _o("tv", "tv", (3.5, 0.3, 1.1), (0.6, 0.1, 0.4), colour="black"),
    ], relations=[("u1", "ON", "t", 0.9), ("u2", "ON", "t", 0.9), ("b1", "ON", "t", 0.9),
                  ("b1", "NEXT_TO", "u1", 0.8), ("c1", "NEXT_TO", "t", 0.8), ("c2", "NEXT_TO", "t", 0.8),
                  ("t", "ON", "floor", 0.9)], room="kitchen", building="home")
    kitchen.up = (0.0, 0.0, 1.0)
    living = graph([
        _o("sofa", "couch", (1, 1, 0.4), (2.0, 0.9, 0.8), colour="grey"),
        _o("lc", "chair", (3, 1, 0.45), (0.5, 0.5, 0.9), colour="red"),
        _o("ltv", "tv", (1, 3, 1.0), (1.0, 0.1, 0.6), colour="black"),
    ], relations=[("lc", "NEXT_TO", "sofa", 0.8)], room="livingroom", building="home")
    ids = dict(merge_local_graph(store, kitchen).node_ids)
    ids.update(merge_local_graph(store, living).node_ids)
    return ids


def ask(store, q, **kw):
    a = answer(store, q, use_embedding=False, **kw)
    assert a.ok, a.text
    return a


def objects(store, room="kitchen"):
    """The stored objects of a room (not structure), from the graph."""
    rows = store.read("object_all", room=f"home/{room}")
    return [dict(r["o"]) for r in rows if (r["o"].get("layer") or "object") != "structure"]


# -- 1. typos only for unknown words -------------------------------------------------------------
def test_correct_words_are_never_corrected():
    from sg3d.queries.reader.typos import typo_vocabulary
    from sg3d.queries.reader.tidy import tidy
    from sg3d.queries.reader.typos import common_words, fix_typos

    assert {"sitting", "cutting", "seat", "someone"} <= common_words()
    text, notes = fix_typos(tidy("how many pieces of furniture for sitting are there?").text, typo_vocabulary())
    assert "sitting" in text.split() and "cutting" not in text.split() and notes == []
    text, notes = fix_typos(tidy("how many chiars are next to the tabel").text, typo_vocabulary())
    assert notes == ["read 'chiars' as 'chairs'", "read 'tabel' as 'table'"]


def test_sitting_is_not_read_as_cutting_on_a_store(store, home):
    a = answer(store, "how many pieces of furniture for sitting are there?", room="kitchen", use_embedding=False)
    assert "cutting" not in a.text and "knife" not in a.text


# -- 2. room names: spaces, case, typos --------------------------------------------------------
def test_room_names_with_spaces_case_and_typos(store, home):
    stored = {o["id"] for o in objects(store, "livingroom")}
    a = ask(store, "what is in the living room?")
    assert {o["id"] for o in a.objects} == stored
    assert "livingroom" in a.text and "room 'living room' read as 'livingroom'" in a.text
    n = len([o for o in objects(store, "livingroom") if o["label"] == "chair"])
    assert ask(store, "how many chairs are in the Living Room?").value == n
    k = len([o for o in objects(store, "kitchen") if o["label"] == "chair"])
    a = ask(store, "how many chairs are in the kitchn?")
    assert a.value == k and "kitchen" in a.text
    a = ask(store, "how many chairs are there?", room="kitchn")
    assert a.value == k and "room 'kitchn' read as 'kitchen'" in a.text
    a = ask(store, "how many chairs are there?", room="living room", building="Home")
    assert a.value == n and "livingroom" in a.text
    a = answer(store, "how many chairs are there?", room="living room", use_embedding=False)
    assert "read as 'livingroom'" in "\n".join(a.explain_lines() + [a.text])


def test_unknown_rooms_stay_unknown(store, home):
    a = answer(store, "how many chairs are there?", room="garage", use_embedding=False)
    assert not a.ok and "garage" in a.text


# -- 3. new phrasings ----------------------------------------------------------------------------
def _centre(o):
    return [float(v) for v in (o.get("box_centre") or [o["x"], o["y"], o["z"]])]


def test_distances_between_two_objects(store, home):
    cups = [o for o in objects(store) if o["label"] == "cup"]
    tv = next(o for o in objects(store) if o["label"] == "tv")
    a = ask(store, "how far apart are the two cups?", room="kitchen")
    assert a.value == pytest.approx(math.dist(_centre(cups[0]), _centre(cups[1])), abs=1e-3) and "apart" in a.text
    a = ask(store, "how far is the cup from the tv?", room="kitchen")
    assert a.value == pytest.approx(min(math.dist(_centre(c), _centre(tv)) for c in cups), abs=1e-3)


def test_size_comparisons_by_box_volume(store, home):
    vol = {o["label"]: max(float(x["volume"]) for x in objects(store) if x["label"] == o["label"])
           for o in objects(store)}
    a = ask(store, "is the cup bigger than the book?", room="kitchen")
    assert a.value is (vol["cup"] > vol["book"])
    a = ask(store, "is the tv bigger than the cup?", room="kitchen")
    assert a.value is (vol["tv"] > vol["cup"]) and a.text.startswith("yes" if a.value else "no")
    a = ask(store, "which is bigger, the cup or the book?", room="kitchen")
    winner = "cup" if vol["cup"] > vol["book"] else "book"
    assert winner in a.value and a.text.startswith("the")


def test_in_how_many_rooms(store, home):
    rooms = {r for r in ("kitchen", "livingroom") if any(o["label"] == "chair" for o in objects(store, r))}
    a = ask(store, "in how many rooms is there a chair?")
    assert a.value == len(rooms) and all(r in a.text for r in rooms)
    assert ask(store, "in how many rooms is there a couch?").value == 1


@pytest.mark.parametrize("question, holds", [
    ("are there at least two tvs?", lambda n: n["tv"] >= 2),
    ("are there at least 4 chairs?", lambda n: n["chair"] >= 4),
    ("are there more than 3 chairs?", lambda n: n["chair"] > 3),
    ("are there at most 2 cups?", lambda n: n["cup"] <= 2),
])
def test_at_least_and_more_than(store, home, question, holds):
    n: dict[str, int] = {}
    for room in ("kitchen", "livingroom"):
        for o in objects(store, room):
            n[o["label"]] = n.get(o["label"], 0) + 1
    assert ask(store, question).value is holds(n)


def test_attribute_only_sets(store, home):
    red = {o["id"] for o in objects(store) if o.get("colour") == "red"}
    a = ask(store, "what is red in the kitchen?")
    assert {o["id"] for o in a.objects} == red and red
    white = {o["id"] for r in ("kitchen", "livingroom") for o in objects(store, r) if o.get("colour") == "white"}
    assert {o["id"] for o in ask(store, "which things are white?").objects} == white


def test_polite_wrappers(store, home):
    n = len([o for o in objects(store) if o["label"] == "chair"])
    assert ask(store, "could you tell me the number of chairs in the kitchen?").value == n
    assert ask(store, "I'd like to know how many chairs there are", room="kitchen").value == n
    assert ask(store, "I would like to know the number of chairs in the kitchen").value == n


def test_take_a_seat_is_sit(store, home):
    a, b = ask(store, "where can someone take a seat?", room="kitchen"), ask(store, "where can I sit?", room="kitchen")
    assert a.value == b.value and set(a.value) == {o["id"] for o in objects(store) if o["label"] == "chair"}


def test_next_to_any_cup(store, home, ):
    cups = {o["id"] for o in objects(store) if o["label"] == "cup"}
    rows = store.read("relation_all", room="home/kitchen", types=["NEXT_TO", "NEAR"])
    near = {e["s"] for e in rows if e["o"] in cups} | {e["o"] for e in rows if e["s"] in cups}
    a = ask(store, "which things are next to a cup?", room="kitchen")
    assert {o["id"] for o in a.objects} == near - cups and near


# -- round two, second part: one reader, and the phrasings of issue 37 --------------------------------
@pytest.fixture
def study(store, home):
    """'study' (building 'home') beside the kitchen: furniture sg3d named from its shape (a desk,
    a cabinet, a couch, a shelf: named_by "shape"), a chair and a bottle on the desk."""
    items = [_o("d", "desk", (1, 1, 0.38), (1.2, 0.6, 0.75), colour="brown"),
             _o("k", "cabinet", (3, 1, 0.5), (0.8, 0.5, 1.0), colour="white"),
             _o("s", "couch", (1, 3, 0.4), (1.8, 0.8, 0.8), colour="brown"),
             _o("h", "shelf", (3, 3, 1.0), (1.0, 0.3, 0.05), colour="white"),
             _o("ch", "chair", (1, 0.4, 0.45), (0.5, 0.5, 0.9), colour="green"),
             _o("bt", "bottle", (1.1, 1.0, 0.85), (0.07, 0.07, 0.2), colour="green")]
    for o in items[:4]:
        o.named_by = "shape"
    study = graph(items, relations=[("bt", "ON", "d", 0.9), ("ch", "NEXT_TO", "d", 0.8)], room="study", building="home")
    ids = dict(home)
    ids.update(merge_local_graph(store, study).node_ids)
    return ids


def _labels(a) -> set:
    return {o["label"] for o in a.objects if isinstance(o, dict) and o.get("label")}


@pytest.mark.parametrize("question, expected", [
    ("is there anything on the table besides the book?", {"u1", "u2"}),
    ("is there anything on the table other than the cups?", {"b1"}),
    ("is there anything on the table that is not a cup?", {"b1"}),
])
def test_anything_besides(store, home, question, expected):
    a = ask(store, question, room="kitchen")
    assert a.value is True and {o["id"] for o in a.objects} == {home[k] for k in expected}
    assert "except" in a.text


@pytest.mark.parametrize("question, holds", [
    ("are there exactly 3 chairs?", True), ("are there exactly two chairs?", False),
    ("do we have at least 3 chairs?", True), ("do we have more than 3 chairs?", False),
])
def test_exactly_and_at_least(store, home, question, holds):
    n = len([o for o in objects(store) if o["label"] == "chair"])
    assert n == 3
    assert ask(store, question, room="kitchen").value is holds


def test_rooms_by_content_and_by_neighbours(store, study):
    per = {r: len(objects(store, r)) for r in ("kitchen", "livingroom", "study")}
    a = ask(store, "which 2 rooms have the fewest objects?")
    assert [v["room"].split("/", 1)[-1] for v in a.value] == sorted(per, key=lambda r: (per[r], r))[:2]
    a = ask(store, "what are the 2 rooms with the most objects?")
    assert [v["n"] for v in a.value] == sorted(per.values(), reverse=True)[:2]
    a = ask(store, "which room has the fewest neighbours?")
    assert a.ok and "neighbour" in a.text
    assert ask(store, "in how many rooms is there a chair?").value == 3


def test_possessives_and_owners(store, home):
    n = len([o for o in objects(store) if o["label"] == "chair"])
    assert ask(store, "how many chairs does the kitchen have?").value == n
    assert ask(store, "how many chairs the kitchen has").value == n
    assert len(ask(store, "what are the kitchen's chairs?").value) == n
    a = ask(store, "the kitchen's chairs")
    assert a.value is True and "3 chairs" in a.text


def test_affordances_through_one_table_with_shape_named_furniture(store, study):
    stored = {o["id"]: o for r in ("kitchen", "livingroom", "study") for o in objects(store, r)}

    def afford(*labels):
        return {i for i, o in stored.items() if o["label"] in labels and o["room"] == "home/study"}

    assert set(ask(store, "where can someone take a seat?", room="study").value) == afford("chair", "couch")
    assert set(ask(store, "where can I store things?", room="study").value) == afford("cabinet", "shelf")
    assert set(ask(store, "where can I work?", room="study").value) == afford("desk")
    assert set(ask(store, "I need something to pour water into", room="study").value) == afford("bottle")
    assert set(ask(store, "where can I put my cup down?", room="study").value) == afford("desk", "shelf", "cabinet")
    a = ask(store, "how many pieces of furniture for sitting are there?", room="study")
    assert a.value == len(afford("chair", "couch")) and "for sitting" in a.text and "cutting" not in a.text
    assert ask(store, "how many things can I sit on?", room="study").value == len(afford("chair", "couch"))


def test_the_x_with_several_asks_which(store, home):
    a = ask(store, "where is the cup?", room="kitchen")
    assert len(a.value) == 2 and "which one did you mean" in a.text
    a = ask(store, "where is a cup?", room="kitchen")
    assert len(a.value) == 2 and "which one" not in a.text
    assert "which one" not in ask(store, "where are all the chairs?", room="kitchen").text


def test_refusals_name_the_word_and_viewpoints_are_read_once(store, home):
    a = answer(store, "how many chairs are near the tv and also singing?", use_embedding=False)
    assert not a.ok and "'also'" in a.text
    a = answer(store, "what is the weather like?", use_embedding=False)
    assert not a.ok and "'weather'" in a.text   # the word no word list holds, not 'like' where reading stopped
    a = answer(store, "is there a chair behind the table as seen from the tv?", room="kitchen", use_embedding=False)
    assert a.ok and a.logical is not None and a.logical["seen_from"] == {"noun": "tv"}
    a = answer(store, "what changed in the kitchen?", use_embedding=False)
    assert not a.ok and "sg3d ask" in a.text and a.logical is not None and a.logical["op"] == "changes"


def test_explain_shows_one_reading_and_its_plan(store, home):
    a = ask(store, "where is the red cup?", room="kitchen")
    lines = a.explain_lines()
    assert sum(x.startswith("logical form:") for x in lines) == 1
    assert any(x.startswith("plan: per-form templates") for x in lines)
    lines = ask(store, "is there anything on the table besides the book?", room="kitchen").explain_lines()
    assert sum(x.startswith("logical form:") for x in lines) == 1 and any(x.startswith("plan: scene read") for x in lines)


# -- 4. constructions from the paraphrase benchmark (benchmarks/paraphrases.md), in other words --
@pytest.fixture
def attic(store, home):
    """'attic' (building 'home'): a lamp the desk is stored UNDER (desk -UNDER-> lamp), a clock
    stored ABOVE a bench, a blue vase and a white bowl ON a cabinet, a fridge."""
    items = [_o("ad", "desk", (1, 1, 0.38), (0.6, 1.4, 0.75), colour="brown"),
             _o("al", "potted plant", (1, 1, 1.4), (0.3, 0.3, 0.5), colour="yellow"),
             _o("ab", "clock", (3, 1, 1.2), (0.4, 0.4, 0.4), colour="brown"),
             _o("ar", "bench", (3, 1, 0.3), (1.5, 0.5, 0.5), colour="red"),
             _o("as", "cabinet", (1, 3, 0.45), (1.6, 0.5, 0.9), colour="white"),
             _o("av", "vase", (1, 3, 1.0), (0.15, 0.15, 0.3), colour="blue"),
             _o("aj", "bowl", (1.3, 3, 0.95), (0.1, 0.1, 0.1), colour="white"),
             _o("af", "refrigerator", (3, 3, 0.9), (0.7, 0.7, 1.8), colour="grey")]
    attic = graph(items, relations=[("ad", "UNDER", "al", 0.9), ("ab", "ABOVE", "ar", 0.9),
                                    ("av", "ON", "as", 0.9), ("aj", "ON", "as", 0.9)],
                  room="attic", building="home")
    ids = dict(home)
    ids.update(merge_local_graph(store, attic).node_ids)
    return ids


def test_where_never_reverses_an_edge(store, attic):
    # the vase and the bowl are on the cabinet: the cabinet is not "on" either of them
    for question in ("whereabouts is the cabinet?", "where is the cabinet?"):
        a = ask(store, question, room="attic")
        rels = [(r["rel"], r["other_id"]) for o in a.value for r in o["relations"]]
        assert ("ON", attic["av"]) not in rels and ("ON", attic["aj"]) not in rels, a.text
        assert "on the blue vase" not in a.text and " vase" not in a.text.split(" is ", 1)[1], a.text
    # the desk -UNDER-> plant edge: the desk is under the plant, the plant is never under the desk
    a = ask(store, "where is the plant?", room="attic")
    assert "under" not in a.text, a.text


def test_above_and_below_read_from_either_end(store, attic):
    a = ask(store, "which things are above the desk?", room="attic")
    assert [o["id"] for o in a.objects] == [attic["al"]], a.text
    assert ask(store, "how many objects are above the desk?", room="attic").value == 1
    a = ask(store, "what is below the clock?", room="attic")
    assert [o["id"] for o in a.objects] == [attic["ar"]], a.text
    a = ask(store, "is there anything under the plant?", room="attic")
    assert a.value is True and [o["id"] for o in a.objects] == [attic["ad"]]
    # the graph's two kinds of beneath (UNDER: covered; BELOW: air between) are both "under" and
    # "below" to people: the desk stored UNDER the plant is below it, the bench below the clock under it
    a = ask(store, "what is below the plant?", room="attic")
    assert [o["id"] for o in a.objects] == [attic["ad"]], a.text
    a = ask(store, "what is under the clock?", room="attic")
    assert [o["id"] for o in a.objects] == [attic["ar"]], a.text
    a = ask(store, "what is on the clock?", room="attic")
    assert a.objects == [], a.text


def test_width_is_the_larger_horizontal_side_and_depth_the_smaller(store, attic):
    a = ask(store, "how wide is the desk?", room="attic")
    assert a.value == pytest.approx(1.4) and "wide" in a.text
    assert ask(store, "what is the depth of the desk?", room="attic").value == pytest.approx(0.6)


def test_cold_storage_and_surfaces_from_the_table(store, attic):
    a = ask(store, "where could I chill my drinks?", room="attic")
    assert a.value == [attic["af"]], a.text
    a = ask(store, "where can I set my keys down?", room="attic")
    assert attic["as"] in a.value and attic["ad"] in a.value, a.text
    a = answer(store, "where can I keep the soup warm?", room="attic", use_embedding=False)
    assert not a.ok and "'warm'" in a.text


def test_not_a_kind_and_not_a_colour(store, attic):
    a = ask(store, "how many objects on the cabinet are not vases?", room="attic")
    assert a.value == 1 and [o["id"] for o in a.objects] == [attic["aj"]]
    assert "except vases" in a.text
    a = ask(store, "is there anything on the cabinet that is not blue?", room="attic")
    assert a.value is True and [o["id"] for o in a.objects] == [attic["aj"]]
    a = ask(store, "is there anything on the cabinet that is not white or blue?", room="attic")
    assert a.value is False


def test_quantities_frames_and_dislocations(store, home):
    chairs = len([o for o in objects(store) if o["label"] == "chair"])
    assert ask(store, "is there exactly one couch?", room="livingroom").value is True
    assert ask(store, "are there more than one tv?", room="livingroom").value is False
    assert ask(store, "how many chairs can you spot?", room="kitchen").value == chairs
    assert ask(store, "the kitchen's chairs: how many do you see?").value == chairs
    assert ask(store, "did you notice a couch?", room="livingroom").value is True
    assert ask(store, "any sofas about?", room="kitchen").value is False
    assert ask(store, "the living room's couch, what colour is it?").value == "grey"
    assert ask(store, "tell me whether there are books on the table, thanks", room="kitchen").value is True
    assert ask(store, "how many objects does this room contain?", room="livingroom").value == 3


def test_distances_asked_in_units_and_between_both(store, home):
    stored = {o["label"]: o for o in objects(store, "livingroom")}
    d = math.dist(_centre(stored["tv"]), _centre(stored["couch"]))
    a = ask(store, "how far is the couch from the tv in centimetres?", room="livingroom")
    assert a.value == pytest.approx(d, abs=0.01) and f"({d * 100:.0f} cm)" in a.text
    a = ask(store, "how many metres is the couch from the tv?", room="livingroom")
    assert a.value == pytest.approx(d, abs=0.01)
    cups = [o for o in objects(store) if o["label"] == "cup"]
    a = ask(store, "what is the distance between both cups on the table?", room="kitchen")
    assert a.value == pytest.approx(math.dist(_centre(cups[0]), _centre(cups[1])), abs=0.01)


def test_rooms_counted_found_and_compared(store, home):
    assert ask(store, "how many rooms contain a tv?").value == 2
    a = ask(store, "in what rooms could we find cups?")
    assert [v["room"] for v in a.value] == ["home/kitchen"]
    a = ask(store, "which room has fewer chairs, the kitchen or the living room?")
    assert a.value["room"] == "home/livingroom", a.text
    assert ask(store, "how many chairs are there throughout all the rooms?").value == 4


# -- round three: constructions a held-out set found refused (issue 37) --------------------------------
@pytest.mark.parametrize("question, expected", [
    ("apart from the book, what is on the table?", {"u1", "u2"}),
    ("other than the red cup, what's on the table?", {"u1", "b1"}),
    ("aside from the cups, is there anything on the table?", {"b1"}),
])
def test_a_fronted_exception_is_read(store, home, question, expected):
    a = ask(store, question, room="kitchen")
    assert {o["id"] for o in a.objects} == {home[k] for k in expected} and "except" in a.text


@pytest.mark.parametrize("question, typed", [
    ("apart from the cup, frobnicate the table", "apart from"),
    ("other than the tv what glimmers on the table", "other than"),
])
def test_a_refusal_names_the_words_typed_never_a_rewrite(store, home, question, typed):
    a = answer(store, question, room="kitchen", use_embedding=False)
    assert not a.ok
    named = a.text.split("; try e.g.")[0]
    assert "'except'" not in named and f"'{typed}'" in named


@pytest.mark.parametrize("question, room, holds", [
    ("do we have a tv?", "kitchen", True), ("got a couch in here?", "kitchen", False),
    ("have we got any cups?", "kitchen", True), ("is there any couch around here?", "livingroom", True),
])
def test_having_and_there_being(store, home, question, room, holds):
    labels = {o["label"] for o in objects(store, room)}
    noun = next(w for w in ("tv", "couch", "cup") if w in question)
    assert holds is (noun in labels)
    assert ask(store, question, room=room).value is holds


def test_distances_to_the_nearest_and_between(store, home):
    tv = next(o for o in objects(store) if o["label"] == "tv")
    chairs = [o for o in objects(store) if o["label"] == "chair"]
    book = next(o for o in objects(store) if o["label"] == "book")
    nearest = min(math.dist(_centre(c), _centre(tv)) for c in chairs)
    for q in ("distance from the tv to the nearest chair?", "how far apart are the tv and the nearest chair?"):
        assert ask(store, q, room="kitchen").value == pytest.approx(nearest, abs=1e-3)
    gap = math.dist(_centre(tv), _centre(book))
    for q in ("what's the gap between the tv and the book?", "how many meters between the tv and the book?"):
        assert ask(store, q, room="kitchen").value == pytest.approx(gap, abs=1e-3)
    a = ask(store, "how many centimetres between the tv and the book?", room="kitchen")
    assert f"({gap * 100:.0f} cm)" in a.text


def test_polite_frames_on_a_store(store, home):
    n = len([o for o in objects(store) if o["label"] == "chair"])
    assert ask(store, "would you mind telling me how many chairs there are?", room="kitchen").value == n
    assert ask(store, "I was wondering how many chairs there are", room="kitchen").value == n
    assert ask(store, "do you know whether there is a tv?", room="kitchen").value is True


@pytest.mark.parametrize("question", ["show me where each chair is", "where is every chair", "where's each chair?"])
def test_where_each(store, home, question):
    a = ask(store, question, room="kitchen")
    chairs = {o["id"] for o in objects(store) if o["label"] == "chair"}
    assert a.form == "where" and {o["id"] for o in a.value} == chairs


def test_stranded_relations(store, home):
    a = ask(store, "what is the book next to?", room="kitchen")
    assert {o["id"] for o in a.objects} == {home["u1"]}
    a = ask(store, "what's the red cup on?", room="kitchen")
    assert {o["id"] for o in a.objects} == {home["t"]}
    a = ask(store, "what are the cups on?", room="kitchen")
    assert {o["id"] for o in a.objects} == {home["t"]}


@pytest.mark.parametrize("question", [
    "which one's bigger: the tv or the book?", "which is smaller, the book or the tv",
    "which of the tv and the book is larger",
])
def test_which_of_two(store, home, question):
    vol = {o["label"]: float(o["volume"]) for o in objects(store) if o["label"] in ("tv", "book")}
    big = max(vol, key=lambda k: vol[k])
    want = big if ("bigger" in question or "larger" in question) else min(vol, key=lambda k: vol[k])
    assert want in ask(store, question, room="kitchen").value


def test_typos_of_question_words_on_a_store(store, home):
    n = len([o for o in objects(store) if o["label"] == "chair"])
    a = ask(store, "hw many chairs are there", room="kitchen")
    assert a.value == n and "read 'hw' as 'how'" in a.text
    a = ask(store, "waht is on the table", room="kitchen")
    assert {o["id"] for o in a.objects} == {home[k] for k in ("u1", "u2", "b1")}
    assert ask(store, "wher is the tv", room="kitchen").form == "where"


def test_modal_affordances_on_a_store(store, home):
    a = ask(store, "which table could I work at?", room="kitchen")
    assert a.value == [home["t"]]
    a = ask(store, "where should I sit down?", room="kitchen")
    assert set(a.value) == {o["id"] for o in objects(store) if o["label"] == "chair"}


def test_where_in_the_house(store, home):
    a = ask(store, "where in the house is there a couch?")
    assert a.form == "where" and "livingroom" in a.text
