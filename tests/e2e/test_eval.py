"""`sg3d eval` on hand-made graphs in the real store, against a hand-written ground truth."""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from sg3d.evaluation.evaluate import evaluate
from sg3d.evaluation.ground_truth import coco_class, parse_gt, relation_type
from sg3d.evaluation.matching import Node, match
from sg3d.graphdb.values import room_id
from tests.scenes import EVAL_BUILDING as BUILDING
from tests.scenes import EVAL_GT as GT
from tests.scenes import EVAL_ROOM as ROOM
from tests.scenes import build_eval_room as build_room

COCO = {"cup", "chair", "dining table", "book", "tv", "mouse", "wine glass", "remote"}

def test_hedged_coco_categories_and_english_predicates_are_normalised():
    assert coco_class("cup", COCO) == ("cup", False)
    assert coco_class("(book)", COCO) == ("book", True)
    assert coco_class("mouse?", COCO) == ("mouse", True)
    assert coco_class("cup? (or wine glass)", COCO) == ("cup", True)
    assert coco_class("remote (nearest COCO)", COCO) == ("remote", True)
    assert coco_class("(none)", COCO) == (None, False)
    assert coco_class(None, COCO) == (None, False)
    assert [relation_type(p) for p in ("on", "next to", "In front of", "above", "leaning on")] == \
        ["ON", "NEXT_TO", "IN_FRONT_OF", "ABOVE", None]


def test_edges_read_symmetric_relations_both_ways_and_skip_viewpoint_gt():
    from sg3d.evaluation.edges import edge_metrics
    from sg3d.evaluation.ground_truth import GTRelation
    from sg3d.evaluation.matching import Matching

    m = Matching(pairs=[("n1", "A", 0.0), ("n2", "B", 0.0), ("n3", "C", 0.0)], spurious=[], duplicates=[], missing=[])
    gt = [GTRelation("B", "next to", "A", "NEXT_TO"), GTRelation("C", "on", "A", "ON"),
          GTRelation("C", "in front of", "B", "IN_FRONT_OF")]
    # the graph stores NEXT_TO once, the other way round from the GT's wording
    e = edge_metrics(gt, [{"s": "n1", "type": "NEXT_TO", "o": "n2"}, {"s": "n3", "type": "ON", "o": "n1"}], m)
    assert (e["checked"], e["found"], e["precision"]) == (2, 2, 1.0)
    assert e["unmapped"]["viewpoint"] == [["C", "in front of", "B"]]
    e2 = edge_metrics(gt, [{"s": "n3", "type": "ON", "o": "n1"}], m)
    assert (e2["checked"], e2["found"]) == (2, 1)


def test_hungarian_matching_is_one_to_one_and_prefers_the_nearer_pair():
    gt = parse_gt({"objects": [
        {"id": "a", "coco_category": "chair", "world_position": [0, 0, 0]},
        {"id": "b", "coco_category": "chair", "world_position": [0.6, 0, 0]}]}, COCO)
    # greedy nearest-first would give n1->a and leave b unmatched (n2 is 0.7 m from a)
    nodes = [Node("n1", "chair", (0.3, 0, 0)), Node("n2", "chair", (-0.4, 0, 0))]
    m = match(nodes, gt.objects, tolerance=0.5)
    assert sorted((n, g) for n, g, _ in m.pairs) == [("n1", "b"), ("n2", "a")]
    assert m.spurious == [] and m.duplicates == [] and m.missing == []


def test_a_big_node_matches_within_half_its_extent():
    gt = parse_gt({"objects": [{"id": "t", "coco_category": "dining table", "world_position": [0, 0, 0]}]}, COCO)
    far = Node("n", "dining table", (0.9, 0, 0))
    assert match([far], gt.objects, 0.5).pairs == []
    assert [p[:2] for p in match([Node("n", "dining table", (0.9, 0, 0), size=(2.2, 0.9, 0.7))],
                                 gt.objects, 0.5).pairs] == [("n", "t")]


def test_eval_report_on_a_known_graph(store):
    nodes = build_room(store)
    gt = parse_gt(GT, COCO)
    answers = {"How many cups are there?": 1, "Is there a tv?": "no", "What colour is the cup?": "White",
               "Where is the chair?": "next to the table"}

    def fake_vqa(store_, question, room=None, building=None):
        if question == "How many books?":
            raise AssertionError("unsure questions must not be asked")
        return {"answer": answers[question]}

    report = evaluate(store, gt, room_id(BUILDING, ROOM), room=ROOM, building=BUILDING, answerer=fake_vqa)
    n, e, v = report["nodes"], report["edges"], report["vqa"]

    assert (n["graph_nodes"], n["gt_detectable"], n["matched"]) == (5, 4, 3)
    assert n["precision"] == pytest.approx(3 / 5) and n["recall"] == pytest.approx(3 / 4)
    assert n["recall_sure"] == pytest.approx(1.0) and (n["gt_unsure"], n["unsure_found"]) == (1, 0)
    pairs = {p["gt"]: p["node"] for p in n["pairs"]}
    assert pairs == {"T": nodes["dining table@0.1"], "C": nodes["cup@0.1"], "H": nodes["chair@3.2"]}
    assert [(d["node"], d["gt"]) for d in n["duplicates"]] == [(nodes["chair@2.8"], "H")]
    assert [s["node"] for s in n["spurious"]] == [nodes["tv@10.0"]]
    assert "nearest_gt" not in n["spurious"][0]    # the GT has no tv at all
    assert [g["gt"] for g in n["missing"]] == ["B"]
    assert [g["gt"] for g in n["not_detectable"]] == ["S"]
    assert [g["gt"] for g in n["unlocated"]] == ["X"]
    assert n["hedged_category"] == ["B"]

    assert (e["gt_relations"], e["checked"], e["found"]) == (5, 2, 1)
    assert e["missed"] == [["H", "next to", "T"]]
    assert e["unmapped"]["end_not_matched"] == [["B", "on", "T"], ["S", "above", "C"]]
    assert e["unmapped"]["unknown_predicate"] == [["C", "leaning on", "T"]]
    assert e["recall"] == pytest.approx(0.5) and e["recall_all"] == pytest.approx(1 / 5)
    # ON and NEXT_TO are judged; BIGGER_THAN is a type the GT never uses
    assert (e["judged"], e["correct"]) == (2, 1) and e["precision"] == pytest.approx(0.5)
    # NEXT_TO is stored once, subject = the smaller id
    assert e["spurious"] == [sorted([nodes["chair@3.2"], nodes["cup@0.1"]])[:1] + ["NEXT_TO"]
                             + sorted([nodes["chair@3.2"], nodes["cup@0.1"]])[1:]]

    status = {q["question"]: q["status"] for q in v["questions"]}
    assert status == {"How many cups are there?": "right", "Is there a tv?": "wrong",
                      "What colour is the cup?": "right", "Where is the chair?": "not scorable"}
    assert (v["sure_questions"], v["scored"], v["right"]) == (4, 3, 2)
    assert v["accuracy"] == pytest.approx(2 / 3) and v["accuracy_all_sure"] == pytest.approx(2 / 4)


def test_a_symmetric_gt_relation_is_found_in_either_direction(store):
    nodes = build_room(store)
    gt = parse_gt({"objects": GT["objects"], "relations": [{"subject": "C", "predicate": "next to", "object": "H"}]},
                  COCO)
    e = evaluate(store, gt, room_id(BUILDING, ROOM), room=ROOM, building=BUILDING, with_vqa=False)["edges"]
    assert (e["checked"], e["found"]) == (1, 1)
    assert nodes  # the graph stores H -NEXT_TO-> C, the GT says C next to H


def test_without_vqa_module_every_question_is_unsupported(store, monkeypatch):
    import sg3d.evaluation.vqa as eval_vqa

    build_room(store)
    monkeypatch.setattr(eval_vqa, "load_answerer", lambda: None)
    v = evaluate(store, parse_gt(GT, COCO), room_id(BUILDING, ROOM), room=ROOM, building=BUILDING)["vqa"]
    assert not v["available"] and v["scored"] == 0 and v["accuracy"] is None
    assert {q["status"] for q in v["questions"]} == {"unsupported"}


def test_cli_json_report(store, embedded_home, tmp_path):
    from sg3d.cli import cli

    build_room(store)
    gt_file = tmp_path / "gt.json"
    gt_file.write_text(json.dumps(GT))
    result = CliRunner().invoke(cli, ["--home", str(embedded_home), "eval", "--gt", str(gt_file), "--room", ROOM,
                                      "--building", BUILDING, "--json", "--no-vqa"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert report["nodes"]["matched"] == 3 and len(report["nodes"]["duplicates"]) == 1
    assert report["edges"]["found"] == 1 and "vqa" not in report

    table = CliRunner().invoke(cli, ["--home", str(embedded_home), "eval", "--gt", str(gt_file), "--room", ROOM,
                                     "--building", BUILDING, "--no-vqa"])
    assert table.exit_code == 0, table.output
    assert "node precision" in table.stdout and "60.0%" in table.stdout


def test_cli_unknown_room_and_bad_gt_are_one_line_errors(store, embedded_home, tmp_path):
    from sg3d.cli import cli

    gt_file = tmp_path / "gt.json"
    gt_file.write_text(json.dumps(GT))
    r = CliRunner().invoke(cli, ["--home", str(embedded_home), "eval", "--gt", str(gt_file), "--room", "nowhere"])
    assert r.exit_code == 2 and "no room 'nowhere'" in r.output
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    r = CliRunner().invoke(cli, ["--home", str(embedded_home), "eval", "--gt", str(bad), "--room", ROOM])
    assert r.exit_code == 2 and "not valid JSON" in r.output


def test_eval_scores_the_real_vqa_answers(store):
    """The real `sg3d.queries.vqa.answer` (an Answer object): counts and yes/no are scored, refusals
    are listed as unsupported, never as right."""
    from sg3d.queries.vqa import answer

    build_room(store)
    gt = parse_gt(GT, COCO)
    report = evaluate(store, gt, room_id(BUILDING, ROOM), room=ROOM, building=BUILDING, answerer=answer)
    status = {row["question"]: row["status"] for row in report["vqa"]["questions"]}
    assert status["How many cups are there?"] == "right"
    assert status["Is there a tv?"] == "right"          # the graph holds a (spurious) tv
    assert status["What colour is the cup?"] == "right"  # factories' default colour is white


def test_eval_reads_labels_with_the_vocabulary_of_ask_and_plan():
    from sg3d.evaluation.evaluate import category_matcher

    same = category_matcher()
    assert same("cup", "cup") and same("Dining  Table", "dining table")
    assert same("mug", "cup") and same("sofa", "couch") and same("magazine", "book")
    assert not same("counter", "dining table")      # no class covers a counter
    assert not same("glass", "cup")                 # a wine glass or a cup: not one class
    assert not same("dish", "bowl")                 # tableware, a group
    gt = parse_gt({"objects": [{"id": "g1", "category": "cup", "coco_category": "cup", "world_position": [0, 0, 1]}]})
    m = match([Node("n1", "mug", (0.02, 0.0, 1.0))], gt.objects, same_category=same)
    assert m.gt_to_node == {"g1": "n1"}


def test_colour_agreement_counts_matched_nodes_whose_gt_has_a_colour(store):
    nodes = build_room(store)
    coloured = json.loads(json.dumps(GT))
    colours = {"T": "brown", "C": "white", "H": "red", "B": "blue"}   # B has no node: not counted
    for o in coloured["objects"]:
        if o["id"] in colours:
            o["colour"] = colours[o["id"]]
    report = evaluate(store, parse_gt(coloured, COCO), room_id(BUILDING, ROOM), room=ROOM, building=BUILDING,
                      with_vqa=False)
    c = report["nodes"]["colour"]
    assert (c["agree"], c["with_colour"]) == (2, 3) and c["agreement"] == pytest.approx(2 / 3)
    by_gt = {p["gt"]: p for p in c["pairs"]}
    assert by_gt["H"] == {"node": nodes["chair@3.2"], "gt": "H", "colour": "black", "gt_colour": "red", "agree": False}
    plain = evaluate(store, parse_gt(GT, COCO), room_id(BUILDING, ROOM), room=ROOM, building=BUILDING, with_vqa=False)
    assert plain["nodes"]["colour"] == {"agree": 0, "with_colour": 0, "agreement": None, "pairs": []}
