"""The checks a live map applies to frames as they arrive, on hand-made data: motion judged frame
by frame (`pose_check.causal_motion_problem`) against the whole-recording verdicts
(`implausible_motion`), the depth size of a recording (`Sequence.depth_size`), and how a map's
summary lists its bad frames (`frames.reason_kind`, `mapping.skipped_by_reason`)."""
from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.app.mapping import SKIPPED_EXAMPLES, skipped_by_reason
from sg3d.ingest.readers.base import SIZE_PROBES, SIZE_WINDOW, _probe_depth_size
from sg3d.ingest.readers.follow import MOTION_RUNS_HELD
from sg3d.ingest.readers.frames import reason_kind
from sg3d.ingest.readers.pose_check import MotionRuns, causal_motion_problem, implausible_motion

HZ30 = 1.0 / 30.0


def at(x: float = 0.0, turn_deg: float = 0.0) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_euler("y", turn_deg, degrees=True).as_matrix()
    pose[0, 3] = x
    return pose


def _names(n: int = 100) -> list[str]:
    return [f"frame-{i:06d}" for i in range(n)]


def _causal(poses, max_runs=None) -> dict[int, str]:
    runs, names, out = MotionRuns(max_runs), _names(len(poses)), {}
    for i, pose in enumerate(poses):
        if pose is not None:
            why = causal_motion_problem(runs, i, pose, i * HZ30, names[i], names.__getitem__)
            if why:
                out[i] = why
    return out


def _path(n: int = 100) -> list:
    return [at(0.01 * i, 0.5 * i) for i in range(n)]


def test_the_limits_are_pinned():
    assert (SIZE_PROBES, SIZE_WINDOW, SKIPPED_EXAMPLES, MOTION_RUNS_HELD) == (5, 50, 3, 32)


def test_a_glitch_and_a_shifted_block_get_the_build_verdicts_frame_by_frame():
    poses = _path()
    poses[25] = poses[25].copy()
    poses[25][0, 3] += 5.0
    for i in range(76, 84):
        poses[i] = poses[i].copy()
        poses[i][0, 3] += 50.0
    poses[50] = None
    whole = implausible_motion(poses, [i * HZ30 for i in range(100)], _names())
    assert sorted(whole) == [25, *range(76, 84)]
    assert _causal(poses) == whole
    assert _causal(poses, max_runs=MOTION_RUNS_HELD) == whole


def test_a_bad_first_frame_is_where_judging_as_frames_arrive_differs():
    # the whole recording names frame 0 (the later path outnumbers it); as frames arrive, frame 0
    # is all there is and frame 1, a tie, is named until the new path outnumbers frame 0
    poses = _path()
    poses[0] = at(0, 180.0)
    assert list(implausible_motion(poses, [i * HZ30 for i in range(100)], _names())) == [0]
    assert list(_causal(poses)) == [1]


def test_runs_held_are_bounded_and_the_path_is_kept():
    # 40 separate jumps that never come back to each other: at most MOTION_RUNS_HELD runs, the
    # path (the first 60 frames) among them
    poses = _path(60) + [at(100.0 * k) for k in range(1, 41)]
    runs = MotionRuns(MOTION_RUNS_HELD)
    names = _names()
    for i, pose in enumerate(poses):
        runs.add(i, pose, i * HZ30, names[i], names.__getitem__)
        assert len(runs.runs) <= MOTION_RUNS_HELD
    assert runs.path is not None and runs.path["count"] == 60


def test_the_depth_size_is_what_most_of_the_first_images_say(tmp_path: Path):
    paths = []
    for i, (w, h) in enumerate([(320, 240)] + [(640, 480)] * 6):
        p = tmp_path / f"{i}.png"
        cv2.imwrite(str(p), np.zeros((h, w), np.uint16))
        paths.append(p)
    assert _probe_depth_size(paths) == ((640, 480), SIZE_PROBES)     # read from SIZE_PROBES headers
    assert _probe_depth_size(paths[:SIZE_PROBES - 1]) == ((640, 480), SIZE_PROBES - 1)
    assert _probe_depth_size([tmp_path / "none.png"]) == (None, 0)


def test_a_reason_kind_leaves_out_frame_names_and_figures():
    assert reason_kind("frame-000059", "frame-000059.depth.png is truncated (no PNG end chunk)") == \
        "depth.png is truncated (no PNG end chunk)"
    assert reason_kind("frame-000045", "missing frame-000045.pose.txt") == "missing pose.txt"
    jump = "the camera jumps 5 m in 0.0333 s (150 m/s; a hand-held or robot camera moves at most 10 m/s) from frame-000024"
    assert reason_kind("frame-000025", jump) == reason_kind("frame-000090", jump.replace("5 m", "7.5 m")
                                                            .replace("000024", "000089"))


def test_the_map_summary_counts_every_bad_frame_and_lists_a_few_per_reason():
    skipped = {f"frame-{i:06d}": f"missing frame-{i:06d}.pose.txt" for i in range(SKIPPED_EXAMPLES + 1)}
    skipped["frame-000100"] = "frame-000100.color.jpg is truncated (no JPEG end marker)"
    out = skipped_by_reason(skipped)
    assert out["skipped"] == SKIPPED_EXAMPLES + 2
    first, second = out["skipped_by_reason"]
    assert first["reason"] == "missing pose.txt" and first["count"] == SKIPPED_EXAMPLES + 1
    assert [f["frame"] for f in first["frames"]] == [f"frame-{i:06d}" for i in range(SKIPPED_EXAMPLES)]
    assert second == {"reason": "color.jpg is truncated (no JPEG end marker)", "count": 1,
                      "frames": [{"frame": "frame-000100", "reason": skipped["frame-000100"]}]}
    assert skipped_by_reason({}) == {"skipped": 0, "skipped_by_reason": []}


def test_a_followed_folder_is_listed_again_when_listing_took_a_fifth_of_the_time_since():
    # LISTING_SHARE, MAX_LISTING_WAIT_S
    from sg3d.ingest.readers.follow import listing_interval

    assert abs(listing_interval(0.01) - 0.05) < 1e-9 and abs(listing_interval(0.09) - 0.45) < 1e-9
    assert listing_interval(0.11) == 0.5 and listing_interval(2.0) == 0.5
