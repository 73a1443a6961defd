"""Rule "could be one" (sg3d/queries/unnamed.py) pinned on both sides, the typical sizes it reads
(sg3d/ingest/data/class_sizes.json, "typical") and how a candidate is said."""
from __future__ import annotations

import pytest

from sg3d.core.model import SHAPE_WORDS
from sg3d.core.shape import shape_class
from sg3d.ingest.objects.existence import class_sizes, class_typical
from sg3d.queries import unnamed
from sg3d.queries.unnamed import could_be, describe

KEYBOARD = {"size": (0.45, 0.15, 0.03), "shapes": ("flat",), "support": "surface"}


@pytest.mark.parametrize("size, fits", [
    ((0.45, 0.14, 0.02), True),
    ((0.674, 0.15, 0.03), True), ((0.676, 0.15, 0.03), False),        # SIZE_FACTOR on the longest side
    ((0.3001, 0.15, 0.03), True), ((0.2999, 0.15, 0.03), False),
    ((0.45, 0.1001, 0.03), True), ((0.45, 0.0999, 0.03), False),      # ... on the middle one
    ((0.45, 0.2249, 0.03), True), ((0.45, 0.2251, 0.03), False),
    ((0.45, 0.15, 0.0499), True), ((0.45, 0.15, 0.0501), False),      # SIZE_SLACK_M past the factor
    ((0.45, 0.15, 0.050000000000000024), True),                       # two 2.5 cm voxels, as built
    ((0.45, 0.15, 0.0101), True), ((0.45, 0.15, 0.0099), False),      # on a thin side
    ((0.02, 0.14, 0.45), True),                                       # sides are compared sorted
    ((0.30, 0.22, 0.02), False),                                      # a sheet of paper: each side fits, not its outline
    ((0.32, 0.159, 0.02), True), ((0.32, 0.161, 0.02), False),        # ASPECT_FACTOR, a rounder outline
    ((0.60, 0.1334, 0.02), True), ((0.60, 0.1332, 0.02), False),      # ... and a longer one
])
def test_size_within_a_factor_on_each_sorted_side(size, fits):
    assert could_be(size, "flat", "desk", KEYBOARD) is fits


def test_shape_class_must_be_the_kinds():
    assert could_be((0.45, 0.14, 0.02), "flat", "desk", KEYBOARD)
    assert not could_be((0.45, 0.14, 0.02), "box-shaped", "desk", KEYBOARD)
    assert not could_be((0.45, 0.14, 0.02), None, "desk", KEYBOARD)
    mouse = class_typical()["mouse"]
    assert could_be((0.11, 0.06, 0.04), None, "desk", mouse)      # a mouse's box fits no class


def test_it_rests_on_the_kinds_usual_support():
    assert could_be((0.45, 0.14, 0.02), "flat", "dining table", KEYBOARD)
    assert could_be((0.45, 0.14, 0.02), "flat", "surface", KEYBOARD)
    assert not could_be((0.45, 0.14, 0.02), "flat", "floor", KEYBOARD)
    assert not could_be((0.45, 0.14, 0.02), "flat", None, KEYBOARD)        # resting on nothing named
    assert not could_be((0.45, 0.14, 0.02), "flat", "chair", KEYBOARD)
    chair = {"size": (0.9, 0.5, 0.5), "shapes": ("tall", "box-shaped", None), "support": "floor"}
    assert could_be((0.5, 0.5, 0.9), "box-shaped", "floor", chair)
    assert not could_be((0.5, 0.5, 0.9), "box-shaped", "desk", chair)
    laptop = class_typical()["laptop"]          # open where one works at it
    assert could_be((0.34, 0.25, 0.22), "box-shaped", "desk", laptop)
    assert could_be((0.34, 0.25, 0.22), "box-shaped", "dining table", laptop)
    assert not could_be((0.34, 0.25, 0.22), "box-shaped", "shelf", laptop)
    either = {**chair, "support": "any"}
    assert could_be((0.5, 0.5, 0.9), "box-shaped", "floor", either)
    assert could_be((0.5, 0.5, 0.9), "box-shaped", "desk", either)
    assert not could_be((0.5, 0.5, 0.9), "box-shaped", "wall", either)


def test_no_size_no_candidate():
    assert not could_be(None, "flat", "desk", KEYBOARD)
    assert not could_be((0.45, 0.14), "flat", "desk", KEYBOARD)
    assert not could_be((0.45, 0.14, 0.0), "flat", "desk", KEYBOARD)


def test_the_typical_sizes_are_sound():
    plausible = class_sizes()
    for label, t in class_typical().items():
        assert list(t["size"]) == sorted(t["size"], reverse=True), label
        assert set(t["shapes"]) <= set(SHAPE_WORDS) | {None}, label
        assert t["support"] in ("surface", "work", "floor", "any"), label
        lo, hi = plausible[label]
        assert lo <= t["size"][0] <= hi, label           # within the class's plausible largest extent


def test_a_keyboard_lying_flat_is_one_of_its_own_kind():
    t = class_typical()["keyboard"]
    assert could_be(t["size"], shape_class(t["size"]), "desk", t)


def test_said_with_what_is_known():
    slab = {"size": [0.45, 0.14, 0.02], "shape": "flat", "colour": "black", "support": "on the desk",
            "room": "home/office"}
    assert describe(slab) == "a flat black object 45x14 cm on the desk"
    assert describe(slab, with_room=True) == "a flat black object 45x14 cm on the desk in the office"
    assert describe({**slab, "shape": "panel", "colour": "orange"}) == \
        "a thin upright orange object 45x14 cm on the desk"
    assert describe({**slab, "shape": None, "colour": None}) == "an object 45x14 cm on the desk"
    assert unnamed.not_named("keyboard", "", [slab]) == \
        "I have not named a keyboard; an unnamed thing of its size and shape: a flat black object 45x14 cm on the desk"
    assert unnamed.none_named("keyboards", " in the office", [slab, slab]).startswith(
        "0 named keyboards in the office; 2 unnamed things could be one: a flat black object")


def test_an_unnamed_support_is_a_surface_when_it_is_wider_and_deeper():
    slab = (0.45, 0.14, 0.02)
    assert unnamed.rests_on("object", (1.30, 0.70, 0.74), slab) == {"surface"}       # a desk top no one named
    assert unnamed.rests_on("object", (0.45, 0.14, 0.30), slab) == {"surface"}       # just as wide and deep
    assert unnamed.rests_on("object", (0.44, 0.70, 0.30), slab) == {"surface"}       # sides compared sorted
    assert unnamed.rests_on("object", (0.449, 0.30, 0.30), slab) == set()            # narrower: it is no top
    assert unnamed.rests_on("object", (0.60, 0.139, 0.30), slab) == set()
    assert unnamed.rests_on("object", None, slab) == set()
    assert unnamed.rests_on("desk") == {"surface", "work"} and unnamed.rests_on("shelf") == {"surface"}
    assert unnamed.rests_on("floor") == {"floor"} and unnamed.rests_on("wall") == set()
    assert could_be(slab, "flat", "object", KEYBOARD, (1.30, 0.70, 0.74))
    assert not could_be(slab, "flat", "object", KEYBOARD, (0.30, 0.20, 0.20))
    laptop = class_typical()["laptop"]                 # an unnamed top is no place one is known to work at
    assert not could_be((0.34, 0.25, 0.22), "box-shaped", "object", laptop, (1.30, 0.70, 0.74))


def test_an_unnamed_support_is_said_by_its_looks():
    row = {"support_label": "object", "support_type": "ON", "support_colour": "grey", "support_size": [2.15, 0.85, 0.85]}
    assert unnamed.support_phrase(row) == "on a grey object 215x85 cm"
    assert unnamed.support_phrase({**row, "support_colour": "orange"}) == "on an orange object 215x85 cm"
    assert unnamed.support_phrase({"support_label": "sink", "support_type": "IN"}) == "in the sink"


def test_a_top_is_flat_and_spans_a_desk_top_of_work():                  # TOP_MIN_AREA_M2
    from sg3d.ingest.discover.furniture import DESK_MIN_AREA
    from sg3d.queries.unnamed import TOP_MIN_AREA_M2, could_be_top

    assert TOP_MIN_AREA_M2 == DESK_MIN_AREA
    assert could_be_top((0.5, 0.31, 0.03), "flat")                     # 0.155 m^2
    assert not could_be_top((0.5, 0.29, 0.03), "flat")                 # 0.145 m^2
    assert not could_be_top((1.2, 0.6, 0.75), "box-shaped")            # a cabinet is no top seen alone
