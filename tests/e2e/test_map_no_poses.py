"""`sg3d map` of a camera that gives no poses, with real frames and a real store:

- the first 150 kitchen frames written at 15 frames/s into a folder WITHOUT pose files (as a bare RGB-D camera's
  recorder writes them) are tracked online while they arrive: objects appear in the store before
  the writer ends, no frame is skipped for a missing pose, the track holds, and the live
  trajectory (`--trajectory-out`) lies within 5 cm of the recorded poses;
- a gap of 20 frames never tracked (a camera dropping them, or a mapper busy elsewhere) is
  bridged: the frames after it get the pose the uninterrupted run gives, within 5 cm / 3 degrees;
- the living room written without its trajectory.log (another layout `sg3d build` reads pose-free).
"""
from __future__ import annotations

import threading
from pathlib import Path

import numpy as np

from benchmarks.live_writer import write_live
from tests.conftest import SHARED, need_shared
from tests.sequences import UnposedSource

KITCHEN = SHARED / "data" / "7scenes-redkitchen"
LIVING = SHARED / "data" / "open3d-livingroom1-micro"


def _writer(src: Path, dst: Path, n: int, fps: float = 30.0, skip: frozenset = frozenset()) -> threading.Thread:
    dst.mkdir(parents=True, exist_ok=True)       # the map follows it from the start
    t = threading.Thread(target=write_live, args=(src, dst, fps, n, 1.0),
                         kwargs={"poses": False, "skip": skip}, daemon=True)
    t.start()
    return t


def _map(store, folder: Path, room: str, trajectory: Path, seen: list):
    from sg3d.app.mapping import MapRequest, map_room
    from sg3d.ingest.pipeline import Settings

    req = MapRequest(folder, room, publish_every=0.5, stop_when_idle=3.0, trajectory_out=trajectory)
    return map_room(store, req, Settings(), on_update=seen.append)


def _ate_against_recorded(trajectory: Path, seq) -> tuple[float, int]:
    """ATE RMSE (metres, after alignment) of a TUM trajectory against the recorded poses of the
    same frames (TUM time x 30 = frame number, as the 7-Scenes and Open3D readers number them)."""
    from sg3d.ingest.poses.trajectory import ate_rmse, read_tum

    times, poses = read_tum(trajectory)
    index = {round(seq.timestamp_of(i) * 30): i for i in range(len(seq))}
    pairs = [(T, seq.frame(index[round(t * 30)]).pose) for t, T in zip(times, poses)]
    return ate_rmse(np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])), len(pairs)


# Measured 2026-12-06 on the first 240 kitchen frames at 30 frames/s, load ~6 on 2 cores: 74 frames
# tracked, none lost, ATE 2.8 cm.
KITCHEN_LIVE_ATE_M = 0.05


def test_kitchen_written_without_poses_is_tracked_and_mapped_live(store, tmp_path):
    from sg3d.ingest.readers import open_sequence

    src = need_shared(KITCHEN, "7-Scenes kitchen")
    folder, trajectory = tmp_path / "frames", tmp_path / "live.tum"
    # a camera at 15 frames/s (a RealSense mode): on 2 cores busy with other work (load ~12) the
    # tracker took 1 frame in 9 at 30 frames/s, gaps past what it bridges (the 30 frames/s figures
    # are bench_map --realtime --no-poses's); 10 s leaves room to show objects before the end
    writer = _writer(src, folder, 150, fps=15.0)
    seen: list = []
    summary = _map(store, folder, "bare", trajectory, seen)
    writer.join()
    f = summary.frames
    reasons = [k["reason"] for k in f["skipped_by_reason"]]
    assert not any(r.startswith("missing") for r in reasons), reasons    # no "missing frame-N.pose.txt"
    assert all(len(k["frames"]) <= 3 for k in f["skipped_by_reason"]), f["skipped_by_reason"]
    assert summary.objects > 0 and summary.first_objects_after_s is not None, summary
    assert any(u["objects"] > 0 and u["state"] == "live" for u in seen), seen   # before the source ended
    # the end catches up: the folder is read again as a build reads it, with the poses tracked
    # live, and the last graph is made of the frames a build detects (at least its 40-frame
    # budget), however few frames tracking could afford
    assert summary.final["as_build"] and summary.final["frames"] >= 40, (summary.final, f)
    t = summary.tracking     # on 2 busy cores tracking takes ~1 frame in 4-15: it must hold across the gaps
    assert t is not None and t["ran"] >= 10 and t["restarts"] == 0 and t["lost"] <= 0.1 * t["ran"], t
    ate, n = _ate_against_recorded(trajectory, open_sequence(src))
    assert n >= 30 and ate <= KITCHEN_LIVE_ATE_M, (ate, n)


def test_living_room_without_trajectory_log_is_mapped(store, tmp_path):
    src = need_shared(LIVING / "trajectory.log", "living room").parent
    folder, trajectory = tmp_path / "frames", tmp_path / "live.tum"
    writer = _writer(src, folder, 120)
    seen: list = []
    summary = _map(store, folder, "bare-living", trajectory, seen)
    writer.join()
    assert summary.frames["received"] >= 110, summary.frames
    assert not any(k["reason"].startswith("missing") for k in summary.frames["skipped_by_reason"]), summary.frames
    # the living room moves fast (1.8 cm a frame): on a busy machine its track may restart; the
    # kitchen test above holds tracking to account, this one the layout
    assert summary.objects > 0 and summary.tracking["ran"] >= 10, summary


# -- a gap bridged ---------------------------------------------------------------------------------

GAP = range(40, 60)          # 20 frames (0.67 s at 30 frames/s; ~8 cm of the kitchen's path)
GAP_M, GAP_DEG = 0.05, 3.0


class _Dropping(UnposedSource):
    """A camera that dropped the frames of GAP: they cannot be read (no frame in between helps)."""

    def frame(self, i: int):
        from sg3d.ingest.readers.frames import FrameError

        if i in GAP:
            raise FrameError(f"frame-{i:06d}", "dropped by the camera")
        return super().frame(i)


def test_a_gap_of_20_frames_is_bridged():
    from sg3d.ingest.poses.online import OnlinePoses
    from sg3d.ingest.poses.tracking import motion_gap
    from sg3d.ingest.readers import open_sequence

    seq = open_sequence(need_shared(KITCHEN, "7-Scenes kitchen"))
    whole, gapped = OnlinePoses(UnposedSource(seq, 90)), OnlinePoses(_Dropping(seq, 90))
    for i in range(90):
        whole.frame(i)
        if i not in GAP:           # never asked for: as a mapper that jumped over them
            gapped.frame(i)
    assert not gapped.lost and len(gapped.poses) == 90 - len(GAP), gapped.lost
    for i in range(GAP.stop, 90):
        metres, degrees = motion_gap(whole.poses[i], gapped.poses[i])
        assert metres <= GAP_M and degrees <= GAP_DEG, (i, metres, degrees)


def test_a_trajectory_out_in_no_folder_is_refused_at_once(store, embedded_home, tmp_path):
    from tests.cli_helpers import one_error_line, sg3d

    out = sg3d(embedded_home, "map", tmp_path, "--room", "x", "--stop-when-idle", "1",
               "--trajectory-out", tmp_path / "nowhere" / "t.tum")
    assert out.returncode == 2 and "--trajectory-out" in one_error_line(out)


# -- a recording written before the map ------------------------------------------------------------
def test_a_folder_written_before_the_map_is_tracked_frame_by_frame(store, tmp_path):
    """Frames that are there when the map starts are a recording nobody waits for: every one is
    tracked, in order (a camera's newest-frame rule tracked 2 of them and left an end graph of
    2 frames), and the last graph is the build's choice over the whole folder."""
    need_shared(KITCHEN, "the kitchen")
    folder = tmp_path / "written"
    write_live(KITCHEN, folder, 1e6, 60, 0.0, poses=False)         # all 60 frames at once
    summary = _map(store, folder, "kitchen-written", tmp_path / "t.tum", [])
    t = summary.tracking
    assert t is not None and t["ran"] == 60 and t["placed"] == 60 and t["skipped"] == 0, t
    assert summary.final["as_build"] and summary.final["frames"] >= 5, summary.final
    assert summary.objects > 0
