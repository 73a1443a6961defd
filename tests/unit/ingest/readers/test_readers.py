"""Sequence readers on small layouts written by the tests themselves."""
from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from sg3d.ingest.readers import SequenceError, open_sequence
from sg3d.ingest.readers.frames import FrameError
from sg3d.ingest.readers.registration import Registration
from tests.sequences import H, K, W, colour_image, depth_ramp_mm, pose_of, write_7scenes


def test_7scenes_reads_frames_and_skips_bad_ones(tmp_path):
    seq = open_sequence(write_7scenes(tmp_path / "seven"), registration=Registration())
    assert seq.layout == "7scenes" and len(seq) == 5
    np.testing.assert_allclose(seq.K, K)
    frames = list(seq.frames())
    assert [f.index for f in frames] == [0, 3, 4]
    f = frames[1]
    assert f.color.shape == (H, W, 3) and f.color.dtype == np.uint8
    assert f.depth.dtype == np.float32 and f.depth.shape == (H, W)
    np.testing.assert_allclose(f.depth[5], depth_ramp_mm(3)[5] / 1000.0, rtol=1e-6)
    assert f.depth[0, 0] == 0 and f.depth[0, 1] == 0  # 0 and 65535 both mean "no depth"
    np.testing.assert_allclose(f.pose, pose_of(3))
    skipped = dict(seq.skipped)
    assert set(skipped) == {"frame-000001", "frame-000002"}
    assert "frame-000001.color.png" in skipped["frame-000001"]
    assert "frame-000002.pose.txt" in skipped["frame-000002"] and "finite" in skipped["frame-000002"]


def test_7scenes_default_registration_shifts_depth(tmp_path):
    root = write_7scenes(tmp_path / "seven", corrupt=None, nan_pose=None)
    plain = open_sequence(root, registration=Registration()).frame(0)
    shifted = open_sequence(root, registration=Registration(offset=(5.0, 0.0))).frame(0)
    # colour pixel u reads depth pixel u + 5
    np.testing.assert_array_equal(shifted.depth[10, 10:50], plain.depth[10, 15:55])
    assert np.all(shifted.depth[10, W - 5:] == 0)  # beyond the depth image: invalid
    kinect = open_sequence(root, registration=Registration.kinect_v1()).frame(0)  # scale 1.09 about (cx, cy), offset (5, 1)
    u = 40
    u_d = round(K[0, 2] + 1.09 * (u - K[0, 2]) + 5)
    assert kinect.depth[20, u] == pytest.approx(plain.depth[20, u_d])


def test_lazy_frames_decode_on_access_and_count_bad_depth(tmp_path):
    root = write_7scenes(tmp_path / "seven", corrupt=None, nan_pose=None)
    (root / "frame-000003.depth.png").write_bytes(b"\x89PNG broken")
    seq = open_sequence(root, registration=Registration())
    frames = list(seq.frames(lazy=True))
    assert len(frames) == 5 and not frames[3].is_loaded
    assert frames[3].gray.shape == (H, W)
    with pytest.raises(FrameError, match="frame-000003.depth.png"):
        _ = frames[3].depth
    assert [name for name, _ in seq.skipped] == ["frame-000003"]
    assert len(list(seq.frames())) == 4  # the eager reader skips it too, counted once
    assert len(seq.skipped) == 1


def test_missing_intrinsics_is_one_clear_error(tmp_path):
    root = write_7scenes(tmp_path / "seven", intrinsics=False)
    with pytest.raises(SequenceError, match="camera-intrinsics.txt"):
        open_sequence(root)
    # ingest knows no front end: the CLI turns it into one line, exit status 2
    from click.testing import CliRunner

    from sg3d.cli import cli

    res = CliRunner().invoke(cli, ["--home", str(tmp_path / "home"), "frames", str(root)])
    assert res.exit_code == 2 and "camera-intrinsics.txt" in res.output
    assert len(res.output.strip().splitlines()) == 1


def test_unknown_or_missing_folder(tmp_path):
    with pytest.raises(SequenceError, match="not found"):
        open_sequence(tmp_path / "nope")
    (tmp_path / "empty").mkdir()
    with pytest.raises(SequenceError, match="cannot tell the layout"):
        open_sequence(tmp_path / "empty")
    with pytest.raises(SequenceError, match="unknown layout"):
        open_sequence(write_7scenes(tmp_path / "seven"), layout="kinectfusion")


def write_tum(root: Path) -> Path:
    (root / "rgb").mkdir(parents=True)
    (root / "depth").mkdir()
    np.savetxt(root / "camera-intrinsics.txt", K)
    rgb_t = [10.00, 10.033, 10.066, 10.100]
    depth_t = [10.01, 10.040, 10.200]        # 10.066 and 10.100 have no depth within 0.02 s...
    depth_t = [10.01, 10.040, 10.075]        # ...except 10.066 (0.009 s); 10.100 has none (0.025 s)
    rgb_lines, depth_lines = ["# timestamp filename"], ["# timestamp filename"]
    for t in rgb_t:
        name = f"rgb/{t:.6f}.png"
        cv2.imwrite(str(root / name), colour_image(int(t * 1000)))
        rgb_lines.append(f"{t:.6f} {name}")
    for t in depth_t:
        name = f"depth/{t:.6f}.png"
        cv2.imwrite(str(root / name), (depth_ramp_mm(0).astype(np.float64) * 5).astype(np.uint16))
        depth_lines.append(f"{t:.6f} {name}")
    (root / "rgb.txt").write_text("\n".join(rgb_lines) + "\n")
    (root / "depth.txt").write_text("\n".join(depth_lines) + "\n")
    q = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))  # 90 degrees about z
    gt = ["# timestamp tx ty tz qx qy qz qw"]
    for k in range(30):
        t = 9.99 + 0.01 * k
        gt.append(f"{t:.4f} {1 + k * 0.01:.4f} 2 3 {q[0]} {q[1]} {q[2]} {q[3]}")
    (root / "groundtruth.txt").write_text("\n".join(gt) + "\n")
    return root


def test_tum_associates_timestamps(tmp_path):
    seq = open_sequence(write_tum(tmp_path / "tum"))
    assert seq.layout == "tum" and len(seq) == 3
    frames = list(seq.frames())
    assert [f.timestamp for f in frames] == pytest.approx([10.0, 10.033, 10.066])
    assert dict(seq.skipped).keys() == {"10.100000"}
    assert "depth.txt" in dict(seq.skipped)["10.100000"]
    f = frames[2]
    np.testing.assert_allclose(f.depth[5], depth_ramp_mm(0)[5] / 1000.0, rtol=1e-4)  # 5000 per metre
    np.testing.assert_allclose(f.pose[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-9)
    # nearest ground truth to 10.066 is 10.07 (k=8)
    np.testing.assert_allclose(f.pose[:3, 3], [1.08, 2, 3], atol=1e-9)


def test_tum_without_intrinsics(tmp_path):
    root = write_tum(tmp_path / "tum")
    (root / "camera-intrinsics.txt").unlink()
    with pytest.raises(SequenceError, match="intrinsics"):
        open_sequence(root)


def write_scannet(root: Path) -> Path:
    for sub in ("color", "depth", "pose", "intrinsic"):
        (root / sub).mkdir(parents=True)
    Kc = np.eye(4)
    Kc[:3, :3] = [[120.0, 0, 64.0], [0, 120.0, 48.0], [0, 0, 1]]   # colour 128x96
    Kd = np.eye(4)
    Kd[:3, :3] = [[60.0, 0, 32.0], [0, 60.0, 24.0], [0, 0, 1]]      # depth 64x48
    np.savetxt(root / "intrinsic" / "intrinsic_color.txt", Kc)
    np.savetxt(root / "intrinsic" / "intrinsic_depth.txt", Kd)
    for i in range(4):
        cv2.imwrite(str(root / "color" / f"{i}.jpg"), cv2.resize(colour_image(i), (128, 96)))
        cv2.imwrite(str(root / "depth" / f"{i}.png"), depth_ramp_mm(i))
        pose = pose_of(i)
        if i == 2:
            pose[:] = -np.inf  # how ScanNet marks frames where tracking was lost
        np.savetxt(root / "pose" / f"{i}.txt", pose)
    return root


def test_scannet_resamples_depth_tocolour_image(tmp_path):
    seq = open_sequence(write_scannet(tmp_path / "scene0000_00"))
    assert seq.layout == "scannet" and len(seq) == 4 and seq.image_size == (128, 96)
    frames = list(seq.frames())
    assert [f.index for f in frames] == [0, 1, 3]
    assert dict(seq.skipped).keys() == {"2"} and "2.txt" in dict(seq.skipped)["2"]
    d = frames[0].depth
    assert d.shape == (96, 128)
    # colour column u sees depth column 32 + 0.5 (u - 64): the ramp advances 5 mm per colour pixel
    assert d[50, 80] == pytest.approx((1000 + 10 * 40) / 1000.0)
    assert d[50, 82] == pytest.approx((1000 + 10 * 41) / 1000.0)


def test_scannet_missing_intrinsics(tmp_path):
    root = write_scannet(tmp_path / "scene")
    (root / "intrinsic" / "intrinsic_color.txt").unlink()
    with pytest.raises(SequenceError, match="intrinsic_color.txt"):
        open_sequence(root)
