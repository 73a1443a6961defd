"""`sg3d eval --report DIR` on a hand-made graph: report files, metrics, the coloured picture."""
from __future__ import annotations

import json

import cv2
import numpy as np
from click.testing import CliRunner

from sg3d.cli import cli
from tests.scenes import EVAL_BUILDING as BUILDING
from tests.scenes import EVAL_GT as GT
from tests.scenes import EVAL_ROOM as ROOM
from tests.scenes import build_eval_room as build_room


def _report(store, home, tmp_path, *extra):
    """`sg3d eval --report DIR` on the hand-made room: (DIR, report.md text, report.html text)."""
    build_room(store)
    gt_file = tmp_path / "gt.json"
    gt_file.write_text(json.dumps(GT))
    out = tmp_path / "rep"
    r = CliRunner().invoke(cli, ["--home", str(home), "eval", "--gt", str(gt_file), "--room", ROOM,
                                 "--building", BUILDING, *extra, "--report", str(out)])
    assert r.exit_code == 0, r.output
    return out, (out / "report.md").read_text(), (out / "report.html").read_text()


def test_report_files_mention_the_metrics_and_colour_the_nodes(store, embedded_home, tmp_path):
    out, md, page = _report(store, embedded_home, tmp_path, "--no-vqa")
    for text in (md, page):
        for metric in ("node precision", "node recall", "edge precision", "duplicate nodes", "missing nodes"):
            assert metric in text
        assert "60.0%" in text and "75.0%" in text       # 3 of 5 nodes right, 3 of 4 GT objects found
    assert "](graph.png)" in md and "data:image/png;base64," in page
    assert "| B | book | no |" in md                                  # the missing GT object is listed
    img = cv2.imread(str(out / "graph.png"))
    assert img.shape == (1200, 1600, 3)
    bgr = img.reshape(-1, 3).astype(int)

    def has(rgb, tol=30):
        return (np.abs(bgr - np.array(rgb[::-1])).max(axis=1) < tol).sum() > 20

    assert has((46, 170, 70)) and has((220, 40, 40)) and has((255, 150, 0))    # matched, spurious, duplicate


def test_report_has_edge_and_vqa_tables_with_the_names_ask_prints(store, embedded_home, tmp_path):
    import re

    from sg3d.app.scene import fetch_scene

    _, md, page = _report(store, embedded_home, tmp_path)
    names = {n.id: n.name for n in fetch_scene(store, BUILDING, ROOM).nodes}
    for text in (md, page):
        assert "Edges by type" in text and "VQA (sure questions)" in text
        assert not re.search(r"o-[0-9a-f]{8,}", text)                 # no node id anywhere
        for q in GT["questions"]:
            if q["sure"]:
                assert q["text"] in text
    # the two chairs are told apart as ask tells them apart ("black chair", "red chair")
    chairs = sorted(v for v in names.values() if "chair" in v)
    assert chairs == ["black chair", "red chair"]
    assert "| black chair | H |" in md or "| red chair | H |" in md      # a matched chair, by name
    assert "| H chair | next to | T table |" in md                       # the missed GT relation, by GT names
