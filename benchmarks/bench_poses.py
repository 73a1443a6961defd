"""Pose estimation on recordings whose poses are withheld: ATE against the given poses and the
time it adds per input frame.

    python -m benchmarks.bench_poses [SEQUENCE ...] [--step N] [--build-room ROOM]

For each sequence (default: the kitchen and the living room under ../shared/data) the poses are
estimated from the images alone (the given ones are only read for the comparison) and the
absolute trajectory error is printed: RMSE of camera positions after a rigid Umeyama alignment,
and evo's figure for the same when evo is installed. `--build-room ROOM` then builds ROOM from
the first sequence on its estimated poses, moved into the given poses' world frame by that
alignment, so `sg3d eval --gt ... --room ROOM` can compare it with ground truth made in that
frame (a development aid; a product build keeps the first camera's frame).
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from ingest.poses.estimate import DEFAULT_STEP
from ingest.poses.sequence import estimate_sequence_poses
from ingest.poses.trajectory import align_trajectory, ate_rmse
from ingest.readers import open_sequence

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
DEFAULT = [DATA / "7scenes-redkitchen", DATA / "open3d-livingroom1-micro"]


def given_poses(seq) -> dict[int, np.ndarray]:
    out = {}
    for i in range(len(seq)):
        try:
            out[i] = seq.frame(i, lazy=True).pose
        except Exception:   # a frame without a usable given pose is not compared
            continue
    return out


def evo_ate(estimate: np.ndarray, reference: np.ndarray):
    """evo's APE (translation part) after its own SE(3) Umeyama alignment; None without evo."""
    try:
        from evo.core import metrics
        from evo.core.trajectory import PoseTrajectory3D
    except ImportError:
        return None
    stamps = np.arange(len(estimate), dtype=float)
    est = PoseTrajectory3D(poses_se3=list(estimate), timestamps=stamps)
    ref = PoseTrajectory3D(poses_se3=list(reference), timestamps=stamps)
    est.align(ref, correct_scale=False)
    ape = metrics.APE(metrics.PoseRelation.translation_part)
    ape.process_data((ref, est))
    return ape.get_statistic(metrics.StatisticsType.rmse)


def decode_ms(seq, step: int) -> float:
    """ms per input frame to only decode what the odometry reads (depth, a half-size colour image)
    of every `step`-th frame: a yardstick measured in the same run, so the ratio survives load."""
    t0 = time.perf_counter()
    for i in range(0, len(seq), step):
        source = seq.pixels(i, registered=False)
        source.depth(), source.preview(2)
    return 1000 * (time.perf_counter() - t0) / len(seq)


def measure(path: Path, step: int) -> dict:
    seq = open_sequence(path)
    given = given_poses(seq)
    decode = decode_ms(seq, step)
    t0 = time.perf_counter()
    est = estimate_sequence_poses(seq, step=step)
    seconds = time.perf_counter() - t0
    common = [i for i in sorted(est.poses) if i in given]
    E = np.array([est.poses[i] for i in common])
    G = np.array([given[i] for i in common])
    return {"sequence": path.name, "frames": len(seq), "placed": len(est.poses), "unplaced": len(est.unplaced),
            "loop_closures": est.loop_closures, "segments": est.segments, "length_m": round(est.length_m, 2),
            "ate_m": round(ate_rmse(E, G), 4), "evo_ate_m": evo_ate(E, G),
            "ms_per_input_frame": round(1000 * seconds / len(seq), 1), "decode_ms_per_input_frame": round(decode, 1)}


def aligned_build(path: Path, room: str, step: int) -> None:
    """Build ROOM on estimated poses moved into the given poses' frame (see the module text)."""
    import ingest.poses.sequence as poses_module
    from sg3d.cli import cli

    original = poses_module.estimate_sequence_poses

    def estimate_then_align(seq, start=0, stop=None, progress=None, **kw):
        given = given_poses(seq)
        est = original(seq, start, stop, step=step, progress=progress)
        common = [i for i in sorted(est.poses) if i in given]
        T = align_trajectory(np.array([est.poses[i] for i in common]), np.array([given[i] for i in common]))
        est.poses = {i: T @ P for i, P in est.poses.items()}
        seq.use_poses(est.poses, est.unplaced)
        return est

    poses_module.estimate_sequence_poses = estimate_then_align  # type: ignore[assignment]  # swapped in for the run
    try:
        cli.main(["build", str(path), "--room", room, "--estimate-poses"], standalone_mode=False, prog_name="sg3d")
    finally:
        poses_module.estimate_sequence_poses = original


def run(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sequences", nargs="*", type=Path, default=None)
    ap.add_argument("--step", type=int, default=DEFAULT_STEP, help="odometry on every N-th frame")
    ap.add_argument("--build-room", default=None, help="also build this room on aligned estimated poses")
    args = ap.parse_args(argv)
    paths = args.sequences or [p for p in DEFAULT if p.is_dir()]
    print(f"load: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; odometry on every {args.step}th frame")
    loads = []
    for path in paths:
        r = measure(path, args.step)
        loads.append(os.getloadavg()[0])
        evo = f", evo {r['evo_ate_m']:.4f} m" if r["evo_ate_m"] is not None else ""
        print(f"{r['sequence']}: ATE {r['ate_m']:.4f} m{evo} over {r['placed']} of {r['frames']} frames "
              f"({r['unplaced']} not placed), {r['loop_closures']} loop closures, {r['segments']} segments, "
              f"{r['length_m']} m travelled; {r['ms_per_input_frame']} ms per input frame "
              f"({r['ms_per_input_frame'] / max(r['decode_ms_per_input_frame'], 1e-9):.1f}x the "
              f"{r['decode_ms_per_input_frame']} ms of decoding its images alone)")
    print(f"load after: {', '.join(f'{v:.2f}' for v in loads)}")
    if args.build_room:
        aligned_build(paths[0], args.build_room, args.step)


if __name__ == "__main__":
    run()
