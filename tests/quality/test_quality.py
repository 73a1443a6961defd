"""Quality floors on real data: a fresh default build of the real kitchen scored against its
ground truth, and of the second room (the Open3D living room, no ground-truth file: its three
objects are asserted by name).

The floors sit just under what the pipeline reaches (docs/figures.md, Table II), so a regression in
frame choice, fusion, existence, relations or answers fails here. Each room is built once.
"""
from __future__ import annotations

import json

import pytest

from tests.cli_helpers import sg3d
from tests.conftest import SHARED

GT = SHARED / "eval" / "kitchen_gt.json"
LIVING = SHARED / "data" / "open3d-livingroom1-micro"

# what a fresh default kitchen build must keep reaching (measured: docs/figures.md, Table II)
MIN_NODE_PRECISION = 0.78
MIN_NODE_RECALL = 0.35
MAX_DUPLICATES = 1
# the relations issue's bar: edge precision >= 0.80 with checked edge recall >= 0.75. (It was 0.72,
# 8 of 11, while the big tv's screen rim, cut free of a welded segment, was a node of its own
# NEXT_TO the tv in place of the small tv; rule "the named object's own edge",
# `discovery.own_edge`, joins it to the tv.)
MIN_EDGE_PRECISION = 0.80
MIN_EDGE_RECALL = 0.75
MIN_VQA_RIGHT = 5
# every object, named or not, against every located GT object (measured: docs/figures.md, Table II:
# 0.62-0.66 at precision 0.86-0.92 over the given poses and four sub-degree pose draws)
MIN_OBJECT_RECALL = 0.62
MIN_OBJECT_PRECISION = 0.85


@pytest.fixture(scope="module")
def home(tmp_path_factory):
    from sg3d.graphdb.embedded import EmbeddedServer

    home = tmp_path_factory.mktemp("quality-home")
    yield home
    EmbeddedServer(home).stop()


@pytest.fixture(scope="module")
def kitchen(home, kitchen_dir):
    if not GT.exists():
        pytest.skip("ground truth ../shared/eval/kitchen_gt.json not found")
    out = sg3d(home, "build", str(kitchen_dir), "--room", "kitchen", "--json")
    assert out.returncode == 0, out.stderr
    report = sg3d(home, "eval", "--gt", str(GT), "--room", "kitchen", "--json")
    assert report.returncode == 0, report.stderr
    return json.loads(out.stdout), json.loads(report.stdout)


def test_kitchen_nodes_keep_their_quality(kitchen):
    build, report = kitchen
    nodes = report["nodes"]
    assert nodes["precision"] >= MIN_NODE_PRECISION, nodes["spurious"]
    assert nodes["recall"] >= MIN_NODE_RECALL, nodes["missing"]
    assert len(nodes["duplicates"]) <= MAX_DUPLICATES, nodes["duplicates"]
    # the existence test did its job: candidates were formed and some were rejected
    assert build["hypotheses"]["formed"] > build["hypotheses"]["kept"] > 0


def test_kitchen_every_object_gets_a_node_and_the_table_reaches_the_floor(kitchen):
    build, report = kitchen
    # the build summary says what depth found that no detector named
    assert build["from_depth"]["unnamed"] > 0 and build["from_depth"]["structure"] > 0, build["from_depth"]
    objects, structure = report["objects"], report["structure"]
    assert objects["unnamed_nodes"] > 0
    assert objects["recall"] >= MIN_OBJECT_RECALL, objects["missing"]
    assert objects["precision"] >= MIN_OBJECT_PRECISION, objects
    assert structure["floor"] and structure["surfaces"], structure
    # the table's whole box: from the floor to its top (about 0.73 m), not its 8 cm top slab
    tables = [f for f in structure["furniture_heights"] if f["label"] == "dining table"]
    assert tables and all(0.65 <= f["height_m"] <= 0.81 for f in tables), tables


def test_kitchen_edges_and_answers_keep_their_quality(kitchen):
    _, report = kitchen
    assert report["edges"]["precision"] >= MIN_EDGE_PRECISION, report["edges"].get("spurious")
    assert report["edges"]["recall"] >= MIN_EDGE_RECALL, report["edges"].get("missed")
    assert report["vqa"]["right"] >= MIN_VQA_RIGHT


def test_kitchen_the_red_shelfs_things_are_nodes_and_its_boards_are_none(kitchen):
    """Rule "a row of things" (`discovery.row_parts`): the things upright on the red wall shelf (its
    top hidden by them, so no surface rule finds it) were one 1.58 m segment, one node; cut at their
    necks, at least 6 of the 8 the annotators placed there (notes "red shelf") are matched (5 before,
    one of them by the small tv's node). Rule "the board's own thickness"
    (`discovery.board_of_surface`): the left counter's worktop edge under its top was a second node of
    a small frame on it; no node repeats a GT object now (2 before)."""
    _, report = kitchen
    gt = json.loads(GT.read_text())
    on_shelf = {o["id"] for o in gt["objects"] if "red shelf" in o["notes"].lower() and "below" not in o["notes"]}
    missing = {m["gt"] for m in report["objects"]["missing"]}
    assert len(on_shelf) == 8 and len(on_shelf - missing) >= 6, sorted(on_shelf & missing)
    assert report["objects"]["duplicates"] == 0


def test_kitchen_the_gamepad_against_the_storage_box_is_a_node_of_its_own(kitchen):
    """Rule "touching, not one colour" (`segments.split_at_colour_edge`): the red game controller
    lies against the white storage box on the table with no neck between them, so the two were one
    node (matched to the box, the controller missing); cut at their colour edge, both are matched."""
    _, report = kitchen
    gt = json.loads(GT.read_text())
    pair = {o["id"] for o in gt["objects"] if o["category"] in ("game controller", "storage container")}
    missing = {m["gt"] for m in report["objects"]["missing"]}
    assert len(pair) == 2 and not pair & missing, sorted(pair & missing)


def test_kitchen_relations_are_consistent(home, kitchen):
    from sg3d.graphdb.checks import relation_contradictions
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.store import Store

    info = EmbeddedServer(home).ensure_running()
    with Store(info.uri, (info.user, info.password), info.database) as store:
        check = relation_contradictions(store, "default/kitchen")
    assert check["pairs"] > 0
    assert check["contradictory_pairs"] == 0 and check["viewpoint_edges"] == 0, check["examples"]
    assert check["non_canonical_symmetric"] == 0


def test_kitchen_cleanup_plan_puts_no_book_or_phone_in_the_sink(home, kitchen):
    out = sg3d(home, "plan", "clean up the table", "--room", "kitchen", "--json")
    assert out.returncode == 0, out.stderr
    placement = json.loads(out.stdout)["placement"]
    for item, where in placement.items():
        if any(word in item for word in ("book", "phone", "laptop", "remote")):
            assert "sink" not in (where["to"] or ""), (item, where)


def test_where_is_the_cup_names_its_support_without_ids(home, kitchen):
    out = sg3d(home, "ask", "where is the cup?", "--room", "kitchen")
    assert out.returncode == 0, out.stderr
    assert "on the" in out.stdout and "o-" not in out.stdout


@pytest.fixture(scope="module")
def living(home):
    if not (LIVING / "trajectory.log").exists():
        pytest.skip("the second room ../shared/data/open3d-livingroom1-micro is not there")
    out = sg3d(home, "build", str(LIVING), "--room", "living", "--building", "flat", "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(sg3d(home, "cypher", "MATCH (o:Object) WHERE o.room = 'flat/living' "
                                          "RETURN o.label AS label, o.layer AS layer", "--json").stdout)
    return json.loads(out.stdout), rows


def test_the_living_room_builds_from_its_own_layout_with_one_chair_and_one_tv(living):
    build, rows = living
    assert build["layout"] == "open3d" and build["frames"]["detected"] >= 40
    named = [r["label"] for r in rows if r["layer"] != "structure" and r["label"] != "object"]
    assert named.count("chair") == 1 and named.count("tv") == 1
    # one named object more at most: the low wooden cabinet, which the COCO detector calls a dining table
    assert len(named) <= 3, named
    # its structure: the floor and walls; what no detector names (curtains, the vase) is there
    # unnamed, a few pieces at most
    structure = [r["label"] for r in rows if r["layer"] == "structure"]
    assert structure.count("floor") == 1 and "wall" in structure, structure
    assert 1 <= sum(r["label"] == "object" for r in rows) <= 10, rows


def test_the_living_rooms_high_preset_adds_its_vase_without_doubling_anything(home):
    """Full frame + tiles find the vase on the cabinet; the chair's back and base boxed in
    different tiles stay one chair and a tile's view of the TV's corner stays the TV."""
    if not (LIVING / "trajectory.log").exists():
        pytest.skip("the second room ../shared/data/open3d-livingroom1-micro is not there")
    out = sg3d(home, "build", str(LIVING), "--room", "living-high", "--building", "flat", "--quality", "high",
               "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(sg3d(home, "cypher", "MATCH (o:Object) WHERE o.room = 'flat/living-high' "
                                          "RETURN o.label AS label, o.layer AS layer", "--json").stdout)
    labels = sorted(r["label"] for r in rows if r["layer"] != "structure" and r["label"] != "object")
    assert labels.count("chair") == 1 and labels.count("tv") == 1 and labels.count("vase") == 1, labels
    assert len(labels) <= 4, labels      # the cabinet again, as in the default build
