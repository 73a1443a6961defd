"""`sg3d frames` end to end through the real CLI group."""
from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
from click.testing import CliRunner

from sg3d.cli import cli
from tests.test_readers import write_7scenes

W, H = 320, 240


def _textured(seed: int, contrast: float = 0.1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    tex = cv2.resize(rng.integers(0, 256, size=(60, 80), dtype=np.uint8), (W, H), interpolation=cv2.INTER_NEAREST)
    grey = (128 + (tex.astype(np.float64) - 128) * contrast).astype(np.uint8)
    return cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)


def write_walk(root: Path, n: int = 12, blurry: tuple[int, ...] = (6,)) -> Path:
    """A camera sliding along a textured wall 2 m away; frames in `blurry` get motion blur."""
    root.mkdir(parents=True)
    np.savetxt(root / "camera-intrinsics.txt", [[300.0, 0, 160.0], [0, 300.0, 120.0], [0, 0, 1]])
    kernel = np.full((1, 15), 1 / 15, np.float32)
    for i in range(n):
        img = _textured(0)
        if i in blurry:
            img = cv2.filter2D(img, -1, kernel)
        cv2.imwrite(str(root / f"frame-{i:06d}.color.png"), img)
        cv2.imwrite(str(root / f"frame-{i:06d}.depth.png"), np.full((H, W), 2000, np.uint16))
        pose = np.eye(4)
        pose[0, 3] = 0.25 * i        # 0.25 m per frame = 37.5 px of image motion
        np.savetxt(root / f"frame-{i:06d}.pose.txt", pose)
    return root


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
