"""Colour across views: the vote in fusion, the second colour through the real store's merge, and
object colours read from real frames of the living room."""
from __future__ import annotations

import os

import numpy as np
import pytest

from sg3d.core.model import COLOUR_NAMES, HIST_SIZE, LocalGraph
from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from sg3d.ingest.detect.models import Detection
from sg3d.ingest.objects import fusion
from sg3d.ingest.objects.attributes import ObjectAttributes, object_colour
from sg3d.ingest.objects.colour import ColourReading
from tests.conftest import SHARED

LIVING = SHARED / "data" / "open3d-livingroom1-micro"


def _reading(**shares) -> ColourReading:
    order = sorted(shares, key=lambda c: -shares[c])
    return ColourReading(order[0], order[1] if len(order) > 1 else None, shares[order[0]],
                         shares[order[1]] if len(order) > 1 else 0.0, 500,
                         tuple(shares.get(c, 0.0) for c in COLOUR_NAMES))


def _sighting(frame: int, reading: ColourReading, weight: float) -> fusion.Sighting:
    attrs = ObjectAttributes(mean=(0.0, 0.0, 0.0), var=(1e-4,) * 3, n_points=50, size=(0.1, 0.1, 0.1),
                             hist=np.ones(HIST_SIZE), colour=reading.name, thumbnail=b"jpg", centre=(0.0, 0.0, 0.0),
                             colour_reading=reading, view_weight=weight)
    return fusion.Sighting.of(frame, Detection((0, 0, 10, 10), ["cup"], [0.8]), attrs, np.eye(3))


def _white_cup_with_red() -> fusion.Hypothesis:
    """Two good views of a mostly white cup with red; three blurred, border-cut views call it brown."""
    good = [_sighting(f, _reading(white=0.65, red=0.3, brown=0.05), 1.0) for f in (1, 2)]
    poor = [_sighting(f, _reading(brown=0.8, white=0.2), 0.1) for f in (3, 4, 5)]
    return fusion.Hypothesis(0, good + poor)


def test_fusion_votes_colour_over_well_seen_views_and_keeps_a_second_colour():
    obs = fusion.fuse("c", _white_cup_with_red(), np.eye(3))
    assert (obs.colour, obs.colour2) == ("white", "red")
    same_weight = fusion.Hypothesis(0, [_sighting(s.frame, s.attrs.colour_reading, 1.0)
                                        for s in _white_cup_with_red().sightings])
    assert fusion.fuse("c", same_weight, np.eye(3)).colour == "brown"   # the weights decide


def test_views_without_a_reading_vote_with_their_colour_name():
    attrs = ObjectAttributes(mean=(0.0, 0.0, 0.0), var=(1e-4,) * 3, n_points=50, size=(0.1, 0.1, 0.1),
                             hist=np.ones(HIST_SIZE), colour="green", thumbnail=b"jpg", centre=(0.0, 0.0, 0.0))
    hyp = fusion.Hypothesis(0, [fusion.Sighting.of(f, Detection((0, 0, 10, 10), ["cup"], [0.8]), attrs, np.eye(3))
                                for f in (1, 2)])
    assert (fusion.fuse("c", hyp, np.eye(3)).colour, fusion.fuse("c", hyp, np.eye(3)).colour2) == ("green", None)


def test_the_second_colour_is_stored_by_the_merge(store):
    obs = fusion.fuse("c", _white_cup_with_red(), np.eye(3))
    merge_local_graph(store, LocalGraph(room="colourroom", building="home", objects=[obs], relations=[]))
    stored = [r["o"] for r in store.read("object_all", room=room_id("home", "colourroom"))]
    assert [(o["label"], o["colour"], o["colour2"]) for o in stored] == [("cup", "white", "red")]


@pytest.fixture(scope="module")
def living_frame():
    if not (LIVING / "trajectory.log").exists():
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail("living-room data not found at ../shared/data/open3d-livingroom1-micro in CI")
        pytest.skip("living-room data not found at ../shared/data/open3d-livingroom1-micro (set SG3D_SHARED)")
    from sg3d.ingest.readers import open_sequence
    return open_sequence(LIVING).frame(60).load()


@pytest.mark.parametrize("label,box,name", [
    ("tv", (455, 0, 640, 110), "black"),          # a black frame around a bright street scene
    ("cabinet", (392, 205, 636, 370), "brown"),   # dark wood
])
def test_living_room_objects_read_as_a_person_sees_them(living_frame, label, box, name):
    reading, weight = object_colour(living_frame, box, label)
    assert reading.name == name and 0.0 < weight <= 1.0


def test_a_screen_read_as_an_ordinary_object_shows_its_picture(living_frame):
    reading, _ = object_colour(living_frame, (455, 0, 640, 110), None)
    assert reading.name != "black"


def test_a_chair_in_sunlight_and_shade_is_white(living_frame):
    reading, _ = object_colour(living_frame, (150, 120, 450, 450), "chair")
    assert reading.name == "white"


def test_a_vase_in_shade_beside_a_bright_screen_is_white(living_frame):
    vase, tv = (570, 125, 625, 208), (455, 0, 640, 110)
    assert object_colour(living_frame, vase, None)[0].name == "grey"   # the picture's white sets the white
    reading, _ = object_colour(living_frame, vase, None, screens=[tv])
    assert reading.name == "white"


def test_the_living_rooms_unnamed_vase_is_white_in_a_default_build(store):
    """The vase no detector names, found in depth (a box-shaped unnamed object), and the chair,
    the TV and the cabinet (named from its shape; the detector says "dining table") as a person
    sees them in frame 60."""
    if not (LIVING / "trajectory.log").exists():
        pytest.skip("living-room data not found at ../shared/data/open3d-livingroom1-micro (set SG3D_SHARED)")
    from sg3d.app.build import BuildRequest, build_room
    from sg3d.ingest.pipeline import Settings

    build_room(store, BuildRequest(sequence=LIVING, room="living", building="flat"), Settings())
    objects = [r["o"] for r in store.read("object_all", room=room_id("flat", "living"))]
    colours = {o["label"]: o["colour"] for o in objects if o["label"] != "object"}
    assert (colours["chair"], colours["tv"], colours["cabinet"]) == ("white", "black", "brown")
    boxes = [o["colour"] for o in objects if o["label"] == "object" and o.get("shape") == "box-shaped"]
    assert boxes == ["white"]


@pytest.fixture(scope="module")
def kitchen(kitchen_dir):
    from sg3d.ingest.readers import open_sequence
    return open_sequence(kitchen_dir)


def test_a_white_cup_in_shade_on_the_kitchen_table_is_white(kitchen):
    frame = kitchen.frame(786).load()
    reading, _ = object_colour(frame, (257, 382, 351, 470), "cup")
    assert reading.name == "white"


def test_a_cup_lit_warm_by_the_table_is_white_under_the_light_of_its_surround(kitchen):
    from sg3d.ingest.objects import colour
    from sg3d.ingest.objects.attributes import clip_box, colour_pixels
    frame = kitchen.frame(295).load()
    box = (492, 295, 535, 349)                                # the cup with red flowers
    reading, _ = object_colour(frame, box, "cup")
    assert reading.name == "white"
    pixels, _ = colour_pixels(frame, clip_box(box, *frame.size))
    whole_frame = colour.read_colour(pixels, colour.frame_cast(frame.color[::16, ::16]))
    assert whole_frame.name != "white"                        # the frame's light is not the cup's
