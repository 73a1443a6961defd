"""Per-frame pose checks, silent decoders and honest messages for files that are not sequences:
real kitchen frames, damaged on disk, read through the real readers (and one real build)."""
from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from sg3d.ingest.readers import SequenceError, open_sequence
from sg3d.ingest.readers.pose_check import pose_problem, rigid
from tests.cli_helpers import sg3d


def test_pose_problem_names_each_rule():
    good = np.eye(4)
    good[:3, 3] = (1.0, -2.0, 0.5)
    assert pose_problem(good) is None
    far = good.copy()
    far[0, 3] = 1e300
    assert "beyond" in pose_problem(far)
    assert "finite" in pose_problem(np.full((4, 4), np.nan))
    sheared = good.copy()
    sheared[0, 1] = 0.3
    assert "rigid" in pose_problem(sheared)
    mirror = good.copy()
    mirror[:3, 0] *= -1
    assert "reflection" in pose_problem(mirror)


def _copy_frames(kitchen_dir, seq, n):
    seq.mkdir(parents=True, exist_ok=True)
    (seq / "camera-intrinsics.txt").write_bytes((kitchen_dir / "camera-intrinsics.txt").read_bytes())
    for i in range(n):
        for ext in ("color.jpg", "depth.png", "pose.txt"):
            (seq / f"frame-{i:06d}.{ext}").write_bytes((kitchen_dir / f"frame-{i:06d}.{ext}").read_bytes())
    return seq


@pytest.fixture(scope="module")
def bad_poses(kitchen_dir, tmp_path_factory):
    """30 real kitchen frames: frame 0 a 1e300 translation, frame 10 all NaN, frame 20 1e300."""
    seq = _copy_frames(kitchen_dir, tmp_path_factory.mktemp("poses") / "seq", 30)
    for i, value in ((0, 1e300), (10, np.nan), (20, 1e300)):
        pose = np.loadtxt(seq / f"frame-{i:06d}.pose.txt")
        if np.isnan(value):
            pose[:] = np.nan
        else:
            pose[:3, 3] = value
        np.savetxt(seq / f"frame-{i:06d}.pose.txt", pose)
    return seq


def test_a_pose_rounded_to_a_few_digits_is_used_as_the_nearest_rotation():
    from scipy.spatial.transform import Rotation

    exact = np.eye(4)
    exact[:3, :3] = Rotation.from_euler("xyz", [12, -31, 77], degrees=True).as_matrix()
    exact[:3, 3] = (0.5, -1.2, 2.0)
    rounded = np.round(exact, 4)                   # as a pose.txt stores it: not quite orthonormal
    assert pose_problem(rounded) is None and np.abs(rounded[:3, :3].T @ rounded[:3, :3] - np.eye(3)).max() > 1e-6
    snapped = rigid(rounded)
    assert np.abs(snapped[:3, :3].T @ snapped[:3, :3] - np.eye(3)).max() < 1e-12
    assert np.abs(snapped - exact).max() < 1e-4 and np.array_equal(snapped[:3, 3], rounded[:3, 3])
    # the same camera as a quaternion (a bag) gives the same matrix
    q = Rotation.from_matrix(rounded[:3, :3]).as_quat()
    assert np.abs(Rotation.from_quat(q).as_matrix() - snapped[:3, :3]).max() < 1e-12


def test_a_bad_pose_skips_only_its_frame(bad_poses):
    seq = open_sequence(bad_poses)
    with warnings.catch_warnings():
        warnings.simplefilter("error")           # no overflow or invalid-value warnings either
        frames = list(seq.frames(lazy=True))
    assert len(frames) == 27
    skipped = dict(seq.skipped)
    assert set(skipped) == {"frame-000000", "frame-000010", "frame-000020"}
    assert "beyond" in skipped["frame-000000"] and "finite" in skipped["frame-000010"]


def test_a_build_with_bad_poses_uses_the_good_frames(bad_poses, tmp_path):
    home = tmp_path / "home"
    out = sg3d(home, "build", str(bad_poses), "--room", "poses", "--json", timeout=600)
    try:
        assert out.returncode == 0, out.stderr[-2000:]
        summary = json.loads(out.stdout)
        reasons = {s["frame"]: s["reason"] for s in summary["frames"]["skipped_frames"]}
        assert {"frame-000000", "frame-000010", "frame-000020"} <= set(reasons)
        for noise in ("RuntimeWarning", "overflow", "Traceback"):
            assert noise not in out.stderr
    finally:
        sg3d(home, "db", "stop")


def test_damaged_images_are_named_and_decoders_print_nothing(kitchen_dir, tmp_path, capfd):
    seq = _copy_frames(kitchen_dir, tmp_path / "seq", 8)
    depth = seq / "frame-000003.depth.png"                       # truncated PNG
    depth.write_bytes(depth.read_bytes()[:3000])
    colour = seq / "frame-000005.color.jpg"                      # garbage inside the JPEG data
    data = bytearray(colour.read_bytes())
    for i in range(2000, len(data) - 2000, 997):
        data[i] = 0xFF if data[i] != 0xFF else 0
    colour.write_bytes(bytes(data))
    crc = seq / "frame-000006.depth.png"                         # one flipped byte: a CRC failure
    data = bytearray(crc.read_bytes())
    data[len(data) // 2] ^= 0x55
    crc.write_bytes(bytes(data))
    capfd.readouterr()
    s = open_sequence(seq)
    frames = list(s.frames())
    err = capfd.readouterr().err
    assert len(frames) == 5
    skipped = dict(s.skipped)
    assert "truncated" in skipped["frame-000003"] and "corrupt" in skipped["frame-000005"]
    assert "CRC" in skipped["frame-000006"]
    for noise in ("libpng", "Corrupt JPEG", "Premature end", "warning"):
        assert noise not in err, err[:500]


@pytest.mark.parametrize("content", [bytes(range(256)) * 4, b"\xff\xd8\xff\xe0\x00\x10JFIF\x00" + b"\x00\xfe" * 300],
                         ids=["garbage", "jpeg"])
def test_a_damaged_bag_is_named_without_its_bytes(tmp_path, content):
    bag = tmp_path / "broken.bag"
    bag.write_bytes(content)
    with pytest.raises(SequenceError) as err:
        open_sequence(bag)
    message = str(err.value)
    assert "broken.bag" in message and message.isprintable() and "\\x" not in message and len(message) < 400


def test_a_file_given_as_the_sequence_says_it_is_a_file(tmp_path):
    path = tmp_path / "frames.txt"
    path.write_text("hello")
    with pytest.raises(SequenceError, match="is a file"):
        open_sequence(path)
