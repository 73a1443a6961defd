"""`sg3d frames` end to end through the real CLI group."""
from __future__ import annotations

import json

import cv2
from click.testing import CliRunner

from sg3d.cli import cli
from tests.sequences import WALK_W as W
from tests.sequences import write_7scenes, write_walk


def test_frames_json_reports_counts(tmp_path):
    seq = write_walk(tmp_path / "walk")
    result = CliRunner().invoke(cli, ["frames", str(seq), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["read"] == 12 and data["skipped"] == 0 and data["blurry"] == 1
    assert data["keyframes"] >= 2 and data["groups"] == data["keyframes"]
    assert sum(len(g) for g in data["groups_frames"]) == data["kept"] == data["keyframes"] + data["anchors"]
    assert 6 not in {i for g in data["groups_frames"] for i in g}
    assert data["fraction_kept"] == round(data["kept"] / data["read"], 4)
    assert data["params"]["t_key"] == 0.2 and data["params"]["abir_gain"] == 10.0


def test_frames_thresholds_change_the_groups(tmp_path):
    seq = write_walk(tmp_path / "walk", blurry=())
    strict = json.loads(CliRunner().invoke(cli, ["frames", str(seq), "--json", "--t-anchor", "0.95"]).stdout)
    loose = json.loads(CliRunner().invoke(cli, ["frames", str(seq), "--json", "--t-anchor", "0.3"]).stdout)
    assert strict["anchors"] > loose["anchors"]


def test_frames_lists_skipped_frames_and_writes_a_sheet(tmp_path):
    seq = write_walk(tmp_path / "walk", blurry=(4, 9))
    (seq / "frame-000002.color.png").write_bytes(b"garbage")
    sheet = tmp_path / "sheet.png"
    result = CliRunner().invoke(cli, ["frames", str(seq), "--sheet", str(sheet)])
    assert result.exit_code == 0, result.output
    assert "skipped" in result.output and "frame-000002.color.png" in result.output
    assert "detected by build" in result.output and "frames/s" in result.output
    img = cv2.imread(str(sheet))
    assert img is not None and img.shape[1] >= 3 * 2 * (W // 4)


def test_frames_limit(tmp_path):
    seq = write_walk(tmp_path / "walk")
    data = json.loads(CliRunner().invoke(cli, ["frames", str(seq), "--json", "--limit", "5"]).stdout)
    assert data["frames"] == 5 and data["read"] == 5


def test_bad_input_is_one_line_exit_2(tmp_path):
    runner = CliRunner()
    missing = runner.invoke(cli, ["frames", str(tmp_path / "absent")])
    assert missing.exit_code == 2 and "not found" in missing.output
    assert len(missing.output.strip().splitlines()) == 1
    seq = write_7scenes(tmp_path / "seven")
    unknown = runner.invoke(cli, ["frames", str(seq), "--layout", "kinectfusion"])
    assert unknown.exit_code == 2 and "unknown layout" in unknown.output
    assert len(unknown.output.strip().splitlines()) == 1
    (seq / "camera-intrinsics.txt").unlink()
    no_k = runner.invoke(cli, ["frames", str(seq)])
    assert no_k.exit_code == 2 and "camera-intrinsics.txt" in no_k.output


def test_frames_on_the_kitchen(kitchen_dir):
    result = CliRunner().invoke(cli, ["frames", str(kitchen_dir), "--json", "--limit", "200"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["read"] == 200 and 0 < data["fraction_kept"] <= 0.15
