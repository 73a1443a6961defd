"""Poses estimated from the images of a recording that has none: trajectory maths checked
against evo, real kitchen stretches with their poses withheld, lost tracking, the plain folder
layout and a RealSense-style ROS bag built end to end."""
from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sg3d.ingest.poses.sequence import estimate_sequence_poses
from sg3d.ingest.poses.trajectory import (
    align_trajectory,
    ate_rmse,
    interpolate_poses,
    read_tum,
    write_tum,
)
from sg3d.ingest.readers import SequenceError, open_sequence
from tests.cli_helpers import sg3d


def _random_trajectory(rng, n=60):
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, :3] = Rotation.from_rotvec(rng.normal(0, 0.3, (n, 3))).as_matrix()
    poses[:, :3, 3] = np.cumsum(rng.normal(0, 0.05, (n, 3)), axis=0)
    return poses


def test_ate_matches_evo_and_alignment_recovers_a_known_motion():
    evo = pytest.importorskip("evo", reason="evo (PyPI) is the reference for ATE")  # noqa: F841
    from evo.core import metrics
    from evo.core.trajectory import PoseTrajectory3D

    rng = np.random.default_rng(3)
    ref = _random_trajectory(rng)
    move = np.eye(4)
    move[:3, :3] = Rotation.from_euler("xyz", [20, -35, 70], degrees=True).as_matrix()
    move[:3, 3] = (1.0, -2.0, 0.5)
    est = np.array([move @ P for P in ref])
    est[:, :3, 3] += rng.normal(0, 0.01, (len(ref), 3))
    T = align_trajectory(est, ref)
    np.testing.assert_allclose(T @ move, np.eye(4), atol=0.01)
    stamps = np.arange(len(ref), dtype=float)
    e, r = PoseTrajectory3D(poses_se3=list(est), timestamps=stamps), PoseTrajectory3D(poses_se3=list(ref), timestamps=stamps)
    e.align(r, correct_scale=False)
    ape = metrics.APE(metrics.PoseRelation.translation_part)
    ape.process_data((r, e))
    assert ate_rmse(est, ref) == pytest.approx(ape.get_statistic(metrics.StatisticsType.rmse), rel=1e-6)
    assert 0.005 < ate_rmse(est, ref) < 0.03


def test_the_sensitivity_yardstick_turns_cameras_by_what_it_says():
    """bench_poses' --perturb-given: cameras turned in place by a smooth rotation of the stated
    amplitude (positions, hence ATE, untouched), which its rotation error reads back."""
    from benchmarks.bench_poses import perturbed, rotation_errors_deg

    ref = _random_trajectory(np.random.default_rng(5), n=400)
    turned = perturbed(dict(enumerate(ref)), 0.5, seed=2)
    est = np.array([turned[i] for i in range(len(ref))])
    np.testing.assert_allclose(est[:, :3, 3], ref[:, :3, 3])
    errors = rotation_errors_deg(est, ref)
    assert errors.max() <= 0.5 * np.sqrt(3) + 1e-9
    assert 0.2 < errors.mean() < 0.8
    assert np.abs(np.diff(errors)).max() < 0.05          # smooth along the sequence, not jitter
    assert rotation_errors_deg(ref, ref).max() < 1e-5


def test_interpolation_and_tum_round_trip(tmp_path):
    a, b = np.eye(4), np.eye(4)
    b[:3, :3] = Rotation.from_euler("z", 90, degrees=True).as_matrix()
    b[:3, 3] = (2.0, 0, 0)
    mid = interpolate_poses([0.0, 1.0], np.array([a, b]), [0.5])[0]
    np.testing.assert_allclose(mid[:3, 3], (1.0, 0, 0), atol=1e-9)
    assert Rotation.from_matrix(mid[:3, :3]).magnitude() == pytest.approx(np.radians(45))
    write_tum(tmp_path / "t.txt", [0.0, 1.0], np.array([a, b]))
    t, back = read_tum(tmp_path / "t.txt")
    np.testing.assert_allclose(back, np.array([a, b]), atol=1e-6)


# -- real frames -------------------------------------------------------------------------------

def _given(kitchen_dir, indices):
    return np.array([np.loadtxt(kitchen_dir / f"frame-{i:06d}.pose.txt") for i in indices])


def _unposed_kitchen(kitchen_dir, tmp_path, indices):
    """A 7-Scenes folder of the given kitchen frames without their .pose.txt files."""
    (tmp_path / "camera-intrinsics.txt").symlink_to(kitchen_dir / "camera-intrinsics.txt")
    for k, i in enumerate(indices):
        for kind, ext in (("color", "jpg"), ("depth", "png")):
            (tmp_path / f"frame-{k:06d}.{kind}.{ext}").symlink_to(kitchen_dir / f"frame-{i:06d}.{kind}.{ext}")
    return tmp_path


def _placed_error(est, source_indices, given):
    """Largest camera-position error of the placed frames after aligning them to the given poses."""
    placed = sorted(est.poses)
    E = np.array([est.poses[k] for k in placed])
    G = given[placed]
    T = align_trajectory(E, G)
    return float(np.linalg.norm((E[:, :3, 3] @ T[:3, :3].T + T[:3, 3]) - G[:, :3, 3], axis=1).max())


def test_kitchen_stretch_without_poses_is_tracked(kitchen_dir, tmp_path):
    indices = list(range(150))
    seq = open_sequence(_unposed_kitchen(kitchen_dir, tmp_path, indices))
    assert not seq.has_poses()
    est = estimate_sequence_poses(seq)
    given = _given(kitchen_dir, indices)
    assert len(est.poses) == 150 and est.unplaced == {}
    assert ate_rmse(np.array([est.poses[i] for i in range(150)]), given) < 0.03
    frame = seq.frame(75)                           # the frames now carry the estimated poses
    np.testing.assert_allclose(frame.pose, est.poses[75])


def _plain_folder(root, kitchen_dir, sources, blank=()):
    """color/ + depth/ + intrinsics.txt from kitchen frames (source index per position), with
    black images and empty depth at the positions in `blank`."""
    (root / "color").mkdir(parents=True)
    (root / "depth").mkdir()
    K = np.loadtxt(kitchen_dir / "camera-intrinsics.txt")
    (root / "intrinsics.txt").write_text(f"{K[0, 0]} {K[1, 1]} {K[0, 2]} {K[1, 2]} 1000\n")
    for k, i in enumerate(sources):
        if k in blank:
            cv2.imwrite(str(root / "color" / f"{k:06d}.png"), np.zeros((480, 640, 3), np.uint8))
            cv2.imwrite(str(root / "depth" / f"{k:06d}.png"), np.zeros((480, 640), np.uint16))
        else:
            (root / "color" / f"{k:06d}.jpg").symlink_to(kitchen_dir / f"frame-{i:06d}.color.jpg")
            (root / "depth" / f"{k:06d}.png").symlink_to(kitchen_dir / f"frame-{i:06d}.depth.png")
    return root


def test_blank_stretch_half_way_names_its_frames_and_keeps_the_rest_right(kitchen_dir, tmp_path):
    sources = list(range(140))
    blank = set(range(60, 80))
    seq = open_sequence(_plain_folder(tmp_path / "rec", kitchen_dir, sources, blank))
    assert seq.layout == "plain" and not seq.has_poses()
    est = estimate_sequence_poses(seq)
    assert blank <= set(est.unplaced)
    assert all("depth" in est.unplaced[k] for k in blank)
    assert est.segments >= 2                        # the track was lost and started again ...
    assert est.linked_segments >= 1                 # ... and found again where it was lost
    assert not set(est.poses) & blank
    assert len(est.poses) >= 115
    assert _placed_error(est, sources, _given(kitchen_dir, sources)) < 0.1


def test_shuffled_stretch_is_never_merged_with_a_wrong_pose(kitchen_dir, tmp_path):
    rng = np.random.default_rng(0)
    foreign = list(rng.permutation(np.arange(500, 700, 10)))      # 20 frames from elsewhere, shuffled
    sources = list(range(60)) + [int(i) for i in foreign] + list(range(60, 120))
    seq = open_sequence(_plain_folder(tmp_path / "rec", kitchen_dir, sources))
    est = estimate_sequence_poses(seq)
    given = _given(kitchen_dir, sources)
    stretch = set(range(60, 80))
    wrong = [k for k in stretch & set(est.poses)]
    # a foreign frame may only be placed where it really is (it was relocalised), never chained on
    if wrong:
        assert _placed_error(est, sources, given) < 0.1
    assert len(stretch - set(est.poses)) >= 15
    assert all(est.unplaced[k] for k in stretch - set(est.poses))
    assert _placed_error(est, sources, given) < 0.1
    assert len(est.poses) >= 110


def test_plain_folder_names_every_missing_piece(tmp_path):
    (tmp_path / "color").mkdir()
    with pytest.raises(SequenceError) as err:
        open_sequence(tmp_path)
    msg = str(err.value)
    assert "depth/" in msg and "intrinsics.txt" in msg and "color/" not in msg.split("missing", 1)[1]


def test_trajectory_out_needs_estimated_poses(kitchen_dir, tmp_path):
    from sg3d.app.build import BuildError, BuildRequest, place_cameras

    seq = open_sequence(kitchen_dir)
    req = BuildRequest(kitchen_dir, "k", trajectory_out=tmp_path / "t.txt")
    with pytest.raises(BuildError, match="--estimate-poses"):
        place_cameras(seq, req, len(seq))
    assert place_cameras(seq, BuildRequest(kitchen_dir, "k"), len(seq)) == {"source": "given"}
    from sg3d.app.build import validate

    with pytest.raises(BuildError, match="no such folder"):
        validate(BuildRequest(kitchen_dir, "k", trajectory_out=tmp_path / "absent" / "t.txt"))


# -- a RealSense-style bag without poses, end to end ----------------------------------------------

def test_realsense_bag_without_poses_builds_end_to_end(kitchen_dir, tmp_path):
    pytest.importorskip("rosbags", reason="rosbags (PyPI) is needed to write ROS bags")
    from tests.bagwriter import frames_from, write_bag

    kitchen = open_sequence(kitchen_dir)
    bag = write_bag(tmp_path / "realsense.bag", frames_from(kitchen, range(0, 120)), kind="ros1", colour="jpeg",
                    poses="none")
    seq = open_sequence(bag)
    assert not seq.has_poses() and seq.sources["poses"].startswith("none")
    out = sg3d(tmp_path / "home", "build", bag, "--room", "own", "--json", "--trajectory-out", tmp_path / "traj.txt")
    sg3d(tmp_path / "home", "db", "stop", timeout=60)
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    poses = summary["poses"]
    assert poses["source"] == "estimated" and poses["placed"] >= 110
    assert 0.3 < poses["trajectory_m"] < 3.0
    assert summary["frames"]["read"] >= 110
    _, traj = read_tum(tmp_path / "traj.txt")
    assert len(traj) == poses["placed"]
    assert ate_rmse(traj, _given(kitchen_dir, range(0, 120))[:len(traj)]) < 0.05


def test_bag_missing_pieces_are_named_at_once(kitchen_dir, tmp_path):
    pytest.importorskip("rosbags", reason="rosbags (PyPI) is needed to write ROS bags")
    from tests.bagwriter import frames_from, write_bag

    bag = write_bag(tmp_path / "colour-only.bag", frames_from(open_sequence(kitchen_dir), range(3)), kind="ros1",
                    poses="none", depth=False)
    with pytest.raises(SequenceError) as err:
        open_sequence(bag)
    assert "depth image topic" in str(err.value) and "aligned_depth_to_color" in str(err.value)


def test_estimate_poses_replaces_given_ones_and_the_summary_says_so(kitchen_dir):
    from sg3d.commands.build import _poses_text
    from sg3d.ingest.poses.sequence import estimate_summary

    seq = open_sequence(kitchen_dir)
    given = seq.frame(100, lazy=True).pose
    est = estimate_sequence_poses(seq, 60, 160)          # only the build's range is estimated
    assert set(est.poses) == set(range(60, 160))
    np.testing.assert_allclose(seq.frame(100, lazy=True).pose, est.poses[100])
    assert np.abs(seq.frame(100, lazy=True).pose - given).max() > 0.01   # another world frame
    from sg3d.ingest.poses.gravity import sample_frames

    assert len(sample_frames(seq, 20, 60, 160)) == 20 and seq.skipped == []   # gravity stays in the range
    summary = estimate_summary(seq, est, "t.txt")
    assert summary["placed"] == 100 and summary["unplaced_frames"] == []
    text = _poses_text(summary)
    assert f"{summary['trajectory_m']:.2f} m travelled" in text and "trajectory in t.txt" in text
