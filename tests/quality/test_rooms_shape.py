"""Rooms no rule was tuned on: the study room's already registered depth read as such, its desks
named from their shape, and the living room's sideboard a cabinet, on the real frames."""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from sg3d.ingest.readers import open_sequence
from tests.cli_helpers import sg3d
from tests.conftest import SHARED

STUDY = SHARED / "data" / "3dmatch-studyroom"
LIVING = SHARED / "data" / "open3d-livingroom1-micro"
KITCHEN = SHARED / "data" / "7scenes-redkitchen"
STUDY_GT = SHARED / "eval" / "studyroom_gt.json"


def need(path):
    if not path.exists():
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"{path} is not there in CI")
        pytest.skip(f"{path} is not there (the rooms beside the repository in ../shared)")


@pytest.mark.parametrize("fragment", ["fragment-1", "fragment-2"])
def test_the_study_rooms_registered_depth_is_read_as_it_is(fragment):
    need(STUDY / fragment)
    seq = open_sequence(STUDY / fragment)
    name, scores = seq.registration_estimate
    assert name == "identity" and seq.registration.is_identity
    assert scores["identity"] > scores["Kinect v1 form"] + 0.3


def test_the_kitchens_depth_gets_the_kinect_rigs_registration():
    need(KITCHEN)
    seq = open_sequence(KITCHEN)
    name, scores = seq.registration_estimate
    assert name == "Kinect v1 form" and not seq.registration.is_identity
    assert scores[name] > scores["identity"] + 0.3


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    need(STUDY / "fragment-2")
    need(STUDY_GT)
    home = tmp_path_factory.mktemp("study-home")
    for fragment in ("fragment-1", "fragment-2"):
        out = sg3d(home, "build", STUDY / fragment, "--room", "study", "--json")
        assert out.returncode == 0, out.stderr
    yield home
    sg3d(home, "db", "stop")


def nodes_of(home, room):
    out = sg3d(home, "export", "--room", room, "--out", "-")
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)["nodes"]


def test_the_study_rooms_desks_are_named_desk_from_their_shape(study):
    desks = [n for n in nodes_of(study, "study") if n["label"] == "desk"]
    assert all(n.get("named_by") == "shape" and n["layer"] == "object" for n in desks)
    truth = [np.array(o["world_position"]) for o in json.loads(STUDY_GT.read_text())["objects"]
             if o["category"] == "desk"]
    found = {i for n in desks for i, p in enumerate(truth)
             if np.linalg.norm(np.array([n["x"], n["y"], n["z"]]) - p) <= 0.5}
    assert len(found) >= 3, [(n["x"], n["y"], n["z"]) for n in desks]
    assert len(desks) <= len(truth)          # one node a desk: the second fragment adds no twin
    for n in desks:
        height = n["size"][2]                # a desk's box stands on the floor up to its top
        assert 0.6 <= height <= 0.8


def test_the_study_room_answers_how_many_desks_from_desk_nodes(study):
    out = sg3d(study, "ask", "how many desks are there?", "--room", "study")
    assert out.returncode == 0, out.stderr
    n = sum(1 for x in nodes_of(study, "study") if x["label"] == "desk")
    assert out.stdout.strip().startswith(f"{n} desk"), out.stdout
    assert "dining table" not in out.stdout


@pytest.fixture(scope="module")
def living_nodes(tmp_path_factory):
    """The living room built as a user would, its nodes."""
    need(LIVING)
    home = tmp_path_factory.mktemp("living-home")
    try:
        out = sg3d(home, "build", LIVING, "--room", "living", "--json")
        assert out.returncode == 0, out.stderr
        return nodes_of(home, "living")
    finally:
        sg3d(home, "db", "stop")


def test_the_living_rooms_sideboard_is_a_cabinet_named_by_its_shape(living_nodes):
    nodes = living_nodes
    cabinets = [n for n in nodes if n["label"] == "cabinet"]
    assert len(cabinets) == 1 and cabinets[0]["named_by"] == "shape"
    assert "dining table" in cabinets[0]["labels"]          # the detector's word is kept behind it
    assert not [n for n in nodes if n["label"] == "dining table"]
    assert cabinets[0]["size"][0] > 0.9                    # the whole sideboard, not the part boxed


def test_the_study_rooms_couch_is_one_node_named_by_its_shape(study):
    """Its seat level and its arm (0.93 m, longer than any chair's) are one couch, whole box."""
    couches = [n for n in nodes_of(study, "study") if n["label"] == "couch"]
    assert len(couches) == 1 and couches[0]["named_by"] == "shape" and couches[0]["layer"] == "object"
    truth = next(np.array(o["world_position"]) for o in json.loads(STUDY_GT.read_text())["objects"]
                 if o["category"] == "couch")
    n = couches[0]
    assert np.linalg.norm(np.array([n["x"], n["y"], n["z"]]) - truth) <= 0.5
    assert max(n["size"][:2]) >= 0.8 and 0.6 <= n["size"][2] <= 1.0


@pytest.fixture(scope="module")
def study_fragment_1():
    """Discovery alone (no detector) on every second frame of the study room's fragment-1."""
    from sg3d.ingest.discover import discovery
    from sg3d.ingest.discover.room_cloud import room_cloud
    from sg3d.ingest.discover.structure import room_structure
    from sg3d.ingest.objects.existence import View
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames

    need(STUDY / "fragment-1")
    seq = open_sequence(STUDY / "fragment-1")
    gravity = estimate_gravity(sample_frames(seq, 20))
    views = [View.of(seq.frame(i)) for i in range(0, len(seq), 2)]
    cloud = room_cloud(views, gravity.up, gravity.floor_height)
    found, _ = discovery.discover([], cloud, room_structure(cloud), lambda i: seq.frame(i).color)
    return cloud, [(o, discovery.gravity_box(o, cloud)) for o in found]


def test_the_couchs_parts_are_no_nodes_of_their_own(study_fragment_1):
    _, found = study_fragment_1
    couches = [(lo, hi) for o, (lo, hi) in found if o.label == "couch"]
    assert len(couches) == 1
    lo, hi = couches[0]
    for o, (a, b) in found:
        if o.label != "couch":
            centre = (a + b) / 2
            assert not ((centre >= lo) & (centre <= hi)).all(), (o.label, a, b)


def test_the_carrels_side_panels_are_part_of_their_desks(study_fragment_1):
    """The panels between the desks (seen edge-on: 0.15 m thick, up to 1.6 m tall) are no nodes."""
    from sg3d.ingest.discover import furniture

    _, found = study_fragment_1
    desks = [box for o, box in found if o.label == "desk"]
    assert len(desks) >= 2
    panels = [(o.label, lo, hi) for o, (lo, hi) in found if o.label != "desk" and o.named_by is None
              and any(furniture.carrel_panel(lo, hi, *d) for d in desks)]
    assert not panels


LIVING_GT = Path(__file__).resolve().parents[2] / "benchmarks" / "rooms" / "livingroom_gt.json"


def _truth(path, category):
    return [np.array(o["world_position"]) for o in json.loads(path.read_text())["objects"]
            if o["category"] == category]


def test_the_living_rooms_curtain_is_one_node(living_nodes):
    """The curtain's folds, seen apart in depth, are one node: two tall white pieces 12 cm apart
    before rule "welded along a wall" (`segments.split_at_wall`, which now cuts the door's frame and
    wall away from it) and rule "one sheet, in pieces" (`discovery.one_sheet`, which joined them
    before that); either rule alone keeps it one node on these frames."""
    (curtain,) = _truth(LIVING_GT, "curtain")
    tall = [n for n in living_nodes if n["layer"] == "object" and n["size"][2] >= 2 * max(n["size"][:2])
            and np.linalg.norm(np.array([n["x"], n["y"], n["z"]]) - curtain) <= 0.5]
    assert len(tall) == 1, [(n["label"], n["x"], n["y"], n["z"], n["size"]) for n in tall]


def test_nothing_seen_through_the_living_rooms_glass_door_is_a_node(living_nodes):
    """Depth goes through the sliding glass door: two white pieces outside it came back as
    segments beyond the wall the door is in. Rule "seen through the wall"
    (`outside.seen_through_wall`) leaves them out: the living room's object nodes are its ground
    truth's six, each its own object within 0.5 m (one to one, least total distance)."""
    from scipy.optimize import linear_sum_assignment

    truth = [np.array(o["world_position"]) for o in json.loads(LIVING_GT.read_text())["objects"]]
    objects = [n for n in living_nodes if n["layer"] == "object"]
    assert len(objects) == len(truth) == 6, [(n["label"], n["x"], n["y"], n["z"]) for n in objects]
    dist = np.array([[np.linalg.norm(np.array([n["x"], n["y"], n["z"]]) - t) for t in truth] for n in objects])
    rows, cols = linear_sum_assignment(dist)
    assert (dist[rows, cols] <= 0.5).all(), dist[rows, cols]


def test_the_bins_are_cut_from_the_whiteboards_wall(study_fragment_1):
    """Rule "welded along a wall" (`segments.split_at_wall`): the bins, the whiteboard and the wall
    behind them were one 1.98 m segment (the wall, 3 m from the camera, is never voted a wall); cut
    at the wall's plane the bins are a node of their own, as tall as bins."""
    cloud, found = study_fragment_1
    bins = _truth(STUDY_GT, "recycling bin") + _truth(STUDY_GT, "trash can")
    near = [(o, lo, hi) for o, (lo, hi) in found
            if min(np.linalg.norm(np.asarray(o.mean) - b) for b in bins) <= 0.5]
    assert near, [(o.label, o.mean) for o, _ in found]
    assert all(float(hi[2] - lo[2]) <= 1.0 for _, lo, hi in near), [(o.mean, o.size) for o, _, _ in near]


def test_the_second_scans_carrel_panels_join_the_stored_desks(study):
    """Rule "a carrel's panel" across scans (`merge_plan.claimed_by_stored_desk`): fragment-2 never
    sees the desk tops, only the panels beside them; no unnamed node is such a panel."""
    from sg3d.core.geometry import carrel_panel, horizontal_frame
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames

    basis = horizontal_frame(estimate_gravity(sample_frames(open_sequence(STUDY / "fragment-1"), 20)).up)
    nodes = nodes_of(study, "study")

    def box(n, top=False):
        """A node's gravity box about its Gaussian mean (the export carries no box centre); a
        desk's mean lies on its top, its box runs down from there."""
        c, half = basis @ np.array([n["x"], n["y"], n["z"]], float), np.asarray(n["size"]) / 2
        if top:
            c[2] -= half[2]
        return c - half, c + half

    desks = [box(n, top=True) for n in nodes if n["label"] == "desk"]
    panels = [n for n in nodes if n["label"] == "object" and n["layer"] == "object"
              and any(carrel_panel(*box(n), *d) for d in desks)]
    assert desks and not panels, [(n["x"], n["y"], n["z"], n["size"]) for n in panels]


def test_no_refrigerator_is_read_over_a_stored_desk(study):
    """Rule "the shape decides" across scans (`merge_plan.desk_named_solid`): fragment-2's detector
    reads a carrel's panel and its desk as a refrigerator (0.37, 12 frames); the stored desk, named
    from its knee space, is no solid box, so the detection is that desk. The room has no
    refrigerator."""
    assert not [n for n in nodes_of(study, "study") if n["label"] == "refrigerator"]


def test_the_study_rooms_chairs_are_measured_off_the_floor(study):
    """Named boxes measured off the floor (`attributes.object_box` with the build's floor height)
    and judged on the median view (`existence.judged_sizes`): the office chairs' per-view boxes no
    longer run along the floor through their open five-star bases (1.7 m in half the views of the
    chair pulled out, which was rejected as too big for a chair), so each chair node is
    chair-sized (a seat 0.45-0.5 m, a base up to 0.7 m), and the chair pulled out is one of them."""
    chairs = [n for n in nodes_of(study, "study") if n["label"] == "chair"]
    assert len(chairs) >= 3
    assert all(max(n["size"][:2]) <= 0.8 for n in chairs), [n["size"] for n in chairs]
    pulled_out = np.array([o["world_position"] for o in json.loads(STUDY_GT.read_text())["objects"]
                           if o["id"] == "S01"][0])
    assert any(np.linalg.norm(np.array([n["x"], n["y"], n["z"]]) - pulled_out) <= 0.5 for n in chairs)
