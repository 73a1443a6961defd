"""ROS bags as sequences: bags written with rosbags' own writers from real kitchen frames read
back as the folder reader reads the same frames."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("rosbags", reason="rosbags (PyPI) is needed to write and read ROS bags")

from sg3d.ingest.readers import SequenceError, open_sequence  # noqa: E402
from tests.bagwriter import frames_from, write_bag  # noqa: E402
from tests.cli_helpers import sg3d_env

INDICES = list(range(0, 200, 10))  # 20 kitchen frames, 1/3 s apart


@pytest.fixture(scope="module")
def kitchen(kitchen_dir):
    return open_sequence(kitchen_dir)


@pytest.fixture(scope="module")
def frames(kitchen):
    return frames_from(kitchen, INDICES)


def _bag_path(tmp_path, kind):
    return tmp_path / ("run.bag" if kind == "ros1" else kind)


CASES = [("ros1", "raw", "topic", "raw"), ("ros1", "jpeg", "tf", "compressedDepth"), ("sqlite3", "raw", "tf", "raw"),
         ("sqlite3", "jpeg", "topic", "raw"), ("mcap", "jpeg", "tf", "raw"), ("mcap", "raw", "topic", "compressedDepth"),
         ("bare-mcap", "raw", "tf", "raw")]


@pytest.mark.parametrize("kind,colour,poses,depth", CASES)
def test_bag_frames_match_folder_frames(tmp_path, kitchen, frames, kind, colour, poses, depth):
    bag = write_bag(_bag_path(tmp_path, kind), frames, kind=kind, colour=colour, poses=poses, depth_format=depth)
    seq = open_sequence(bag)
    assert seq.layout == "rosbag"
    assert len(seq) == len(INDICES) and seq.skipped == []
    assert seq.image_size == kitchen.image_size
    np.testing.assert_allclose(seq.K, kitchen.K)
    assert ("/tf" in seq.sources["poses"]) == (poses == "tf")
    assert seq.sources["depth"].startswith("/camera/aligned_depth_to_color/image_raw" +
                                           ("/compressedDepth" if depth == "compressedDepth" else " "))
    got = list(seq.frames(lazy=True))
    assert len(got) == len(INDICES)
    for f, i in zip(got, INDICES):
        ref = kitchen.frame(i)
        assert np.array_equal(f.color, ref.color)     # rgb8 raw and the original JPEG both decode exactly
        assert np.array_equal(f.gray, ref.gray)
        assert np.abs(f.depth - ref.depth).max() <= 0.0005 + 1e-6  # millimetres in the bag
        # the kitchen's poses are orthonormal to ~1e-4; quaternions re-orthonormalise them
        assert np.abs(f.pose - ref.pose).max() < 1e-3
        np.testing.assert_allclose(f.K, ref.K)


def test_unknown_encoding_and_missing_tf_are_counted_not_fatal(tmp_path, frames):
    # /tf is missing for the last 3 frames: nothing brackets them, none within the tolerance
    bag = write_bag(tmp_path / "gap.bag", frames, kind="ros1", poses="tf", drop_tf={17, 18, 19})
    seq = open_sequence(bag)
    assert len(seq) == 17
    reasons = dict(seq.skipped)
    assert set(reasons) == {"frame-000017", "frame-000018", "frame-000019"}
    assert all("no /tf world -> base_link" in r for r in reasons.values())

    bag = write_bag(tmp_path / "yuv", frames[:4], kind="mcap", encoding="yuv422")
    seq = open_sequence(bag)
    assert len(seq) == 4
    assert list(seq.frames()) == []                      # every frame fails to decode ...
    assert len(seq.skipped) == 4                          # ... and each is counted once, with the reason
    assert all("unknown colour encoding 'yuv422'" in r for _, r in seq.skipped)


def test_unsynchronised_depth_is_skipped_with_its_reason(tmp_path, frames):
    # colour at 0, 33, 67, 100, 133 ms; depth 100 ms later: only the last two colour frames have
    # a depth image within 20 ms (the depth images of frames 0 and 1)
    bag = write_bag(tmp_path / "late.bag", frames[:5], kind="ros1", depth_offset=0.1)
    seq = open_sequence(bag)
    assert [f.name for f in seq.frames(lazy=True)] == ["frame-000003", "frame-000004"]
    assert np.array_equal(seq.frame(0).depth, open_sequence(bag, max_dt=0.5).frame(0).depth)
    assert [name for name, _ in seq.skipped] == ["frame-000000", "frame-000001", "frame-000002"]
    assert all("no depth on /camera/aligned_depth_to_color/image_raw within 0.02 s" in r for _, r in seq.skipped)
    with pytest.raises(SequenceError, match="no colour frame .* has depth and a pose: 5x no depth on"):
        open_sequence(write_bag(tmp_path / "later.bag", frames[:5], kind="ros1", depth_offset=1.0))


def _cli(*args, env=None):
    return subprocess.run([sys.executable, "-m", "sg3d", *map(str, args)], capture_output=True, text=True, env=env)


def test_bad_bags_are_one_line_and_exit_2(tmp_path, frames):
    """Two colour topics without --color-topic, a truncated file, no depth topic and no pose
    source: each one line on stderr and exit 2."""
    two = write_bag(tmp_path / "two.bag", frames[:3], kind="ros1", extra_colour_topic=True)
    r = _cli("frames", two)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert "2 colour image topics" in r.stderr and "/camera/ir/image_raw (sensor_msgs/Image)" in r.stderr
    assert "--color-topic" in r.stderr
    r = _cli("frames", two, "--color-topic", "/camera/ir/image_raw", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["frames_in_sequence"] == 3 and out["sources"]["color"].startswith("/camera/ir/image_raw")

    good = write_bag(tmp_path / "good.bag", frames[:3], kind="ros1", poses="tf")
    truncated = tmp_path / "truncated.bag"
    truncated.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    r = _cli("frames", truncated)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "cannot read ROS bag" in r.stderr

    r = _cli("frames", good, "--world-frame", "map")
    assert r.returncode == 2 and "no transform chain from camera_color_optical_frame to map" in r.stderr
    r = _cli("frames", good, "--pose-topic", "/nothing")
    assert r.returncode == 2 and "--pose-topic /nothing: no such topic" in r.stderr
    r = _cli("frames", write_bag(tmp_path / "nodepth.bag", frames[:3], kind="ros1", depth=False))
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "lacks a depth image topic" in r.stderr and "/camera/color/image_raw" in r.stderr
    r = _cli("frames", write_bag(tmp_path / "nopose", frames[:3], kind="sqlite3", poses="none"))
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "no pose source in" in r.stderr
    r = _cli("frames", tmp_path / "absent.mcap")
    assert r.returncode == 2 and "ROS bag not found" in r.stderr


@pytest.fixture(scope="module")
def home(tmp_path_factory):
    from sg3d.graphdb.embedded import EmbeddedServer

    home = tmp_path_factory.mktemp("bags-home")
    yield home
    EmbeddedServer(home).stop()


BUILD_FRAMES = range(200, 300)  # 100 consecutive kitchen frames: the folder build keeps ~11 objects

# Four builds cover every dimension at least once: container kind (ROS1 .bag, ROS2 sqlite3, ROS2
# MCAP, bare .mcap), colour (raw rgb8 Image, JPEG CompressedImage), pose source (PoseStamped
# topic, /tf + /tf_static chain) and depth (raw 16UC1 Image, compressedDepth PNG).
BUILD_CASES = [("ros1", "raw", "topic", "raw"), ("sqlite3", "jpeg", "tf", "compressedDepth"),
               ("mcap", "raw", "tf", "raw"), ("bare-mcap", "jpeg", "topic", "compressedDepth")]


def _env(home):
    return sg3d_env(home)


def _built_objects(home, building):
    """Sorted (label, position) of a building's objects, read back through `sg3d export`."""
    r = _cli("export", "--building", building, env=_env(home))
    assert r.returncode == 0, r.stderr
    return sorted((n["label"], (n["x"], n["y"], n["z"])) for n in json.loads(r.stdout)["nodes"])


@pytest.fixture(scope="module")
def folder_objects(kitchen, home):
    """The same 100 frames built from the folder, once for every bag build."""
    r = _cli("build", kitchen.path, "--start", BUILD_FRAMES.start, "--stop", BUILD_FRAMES.stop, "--room", "kitchen",
             "--building", "folder", "--json", env=_env(home))
    assert r.returncode == 0, r.stderr
    objects = _built_objects(home, "folder")
    assert len(objects) >= 3, f"the folder build of frames {BUILD_FRAMES} keeps too few objects to compare"
    return objects


@pytest.fixture(scope="module")
def build_frames(kitchen):
    return frames_from(kitchen, BUILD_FRAMES)


@pytest.mark.parametrize("kind,colour,poses,depth", BUILD_CASES)
def test_sg3d_build_from_a_bag(tmp_path, home, folder_objects, build_frames, kind, colour, poses, depth):
    """A 100-frame bag, written with rosbags' own writer, built end to end by `sg3d build` into a
    real store gives the same objects as the folder of the same frames: the same count and
    labels, positions within 1 cm.

    Four builds (not 4 x 2 x 2 x 2: each takes ~20 s) and every dimension appears at least once:
    ROS1 .bag (raw rgb8, PoseStamped, raw 16UC1), ROS2 sqlite3 (JPEG, /tf, compressedDepth),
    ROS2 MCAP (raw rgb8, /tf, raw 16UC1), bare .mcap (JPEG, PoseStamped, compressedDepth)."""
    bag = write_bag(_bag_path(tmp_path, kind), build_frames, kind=kind, colour=colour, poses=poses,
                    depth_format=depth)
    building = f"{kind}-{colour}-{poses}-{depth}"
    r = _cli("build", bag, "--room", "kitchen", "--building", building, "--json", env=_env(home))
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert summary["frames"]["read"] == len(BUILD_FRAMES) and summary["frames"]["skipped"] == 0, summary["frames"]["skipped_frames"]
    from_bag = _built_objects(home, building)
    assert len(from_bag) == len(folder_objects)
    assert [label for label, _ in from_bag] == [label for label, _ in folder_objects]
    for (label, a), (_, b) in zip(from_bag, folder_objects):
        assert np.abs(np.subtract(a, b)).max() < 0.01, f"{label}: {a} from the bag, {b} from the folder"
