"""Ground truth read for judging: COCO classes, and the furniture sg3d names from its shape."""
from __future__ import annotations

from sg3d.evaluation.ground_truth import parse_gt

NAMES = {"chair", "cup", "dining table"}


def gt(*objects):
    return parse_gt({"objects": [dict(id=f"G{i}", world_position=[0, 0, 0], **o) for i, o in enumerate(objects)]},
                    coco_names=NAMES)


def test_a_desk_without_a_coco_class_is_judged_as_a_desk():
    g = gt({"category": "desk", "coco_category": "(none)"}, {"category": "Cabinet", "coco_category": None})
    assert [o.coco for o in g.objects] == ["desk", "cabinet"]


def test_other_free_names_stay_unnameable():
    g = gt({"category": "wall cabinets", "coco_category": "(none)"},
           {"category": "study carrel / cubicle", "coco_category": "(none)"})
    assert [o.coco for o in g.objects] == [None, None]


def test_a_coco_class_wins_over_the_category():
    g = gt({"category": "desk", "coco_category": "dining table"})
    assert g.objects[0].coco == "dining table"
