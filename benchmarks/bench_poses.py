"""Pose estimation on recordings whose poses are withheld: ATE against the given poses and the
time it adds per input frame.

    python -m benchmarks.bench_poses [SEQUENCE ...] [--step N] [--build-room ROOM [--perturb-given DEG]]
    python -m benchmarks.bench_poses [SEQUENCE ...] --frame-sets [--perturb-given DEG] [--seeds N]

For each sequence (default: the kitchen and the living room under ../shared/data) the poses are
estimated from the images alone (the given ones are only read for the comparison) and the
absolute trajectory error is printed: RMSE of camera positions after a rigid Umeyama alignment,
and evo's figure for the same when evo is installed. `--build-room ROOM` then builds ROOM from
the first sequence on its estimated poses, moved into the given poses' world frame by that
alignment, so `sg3d eval --gt ... --room ROOM` can compare it with ground truth made in that
frame (a development aid; a product build keeps the first camera's frame). With
`--perturb-given DEG` that build uses the given poses turned by a smooth rotation of DEG instead:
the yardstick for how far the graph moves under a pose error of a given size.

`--frame-sets` runs only the build's frame choice (blur rejection, KGE, coverage: no detection)
on the given poses, on the given poses turned by `--perturb-given` (default 0.3 degrees) for
`--seeds` seeds, and on the estimated poses, and prints the Jaccard overlap of each detected
frame set with the given poses' set: how much the detected frames, and so the graph, depend on
a sub-degree pose difference. The time of one frame choice is printed beside it.
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from sg3d.ingest.poses.estimate import DEFAULT_STEP
from sg3d.ingest.poses.sequence import estimate_sequence_poses
from sg3d.ingest.poses.trajectory import align_trajectory, ate_rmse
from sg3d.ingest.readers import open_sequence

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


def rotation_errors_deg(estimate: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per-frame angle between estimated and given camera orientation after the ATE's alignment."""
    T = align_trajectory(estimate, reference)
    R = np.einsum("ij,njk->nik", T[:3, :3], estimate[:, :3, :3])
    cos = (np.einsum("nij,nij->n", R, reference[:, :3, :3]) - 1) / 2
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


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
    t0, c0 = time.perf_counter(), time.process_time()
    est = estimate_sequence_poses(seq, step=step)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    common = [i for i in sorted(est.poses) if i in given]
    E = np.array([est.poses[i] for i in common])
    G = np.array([given[i] for i in common])
    return {"sequence": path.name, "frames": len(seq), "placed": len(est.poses), "unplaced": len(est.unplaced),
            "loop_closures": est.loop_closures, "segments": est.segments, "length_m": round(est.length_m, 2),
            "ate_m": round(ate_rmse(E, G), 4), "evo_ate_m": evo_ate(E, G),
            "rotation_error_deg": round(float(rotation_errors_deg(E, G).mean()), 2),
            "ms_per_input_frame": round(1000 * seconds / len(seq), 1),
            "cpu_ms_per_input_frame": round(1000 * cpu / len(seq), 1), "decode_ms_per_input_frame": round(decode, 1)}


def perturbed(poses: dict[int, np.ndarray], degrees: float, seed: int) -> dict[int, np.ndarray]:
    """The poses, each camera turned by a rotation that varies smoothly along the sequence: per
    axis `degrees` * sin(2 pi i / period + phase), periods of 150-400 frames (drift-like, not jitter)."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    phase, period = rng.uniform(0, 2 * np.pi, 3), rng.uniform(150, 400, 3)
    out = {}
    for i, P in poses.items():
        turn = np.eye(4)
        turn[:3, :3] = Rotation.from_rotvec(np.radians(degrees) * np.sin(2 * np.pi * i / period + phase)).as_matrix()
        out[i] = P @ turn
    return out


def aligned_build(path: Path, room: str, step: int, perturb_deg: float | None = None, seed: int = 1,
                  quality: str | None = None) -> None:
    """Build ROOM on estimated poses moved into the given poses' frame (see the module text), or,
    with `perturb_deg`, on the given poses turned by `perturbed` (how much the graph changes
    under a pose error of that size, through the same code path)."""
    import sg3d.ingest.poses.sequence as poses_module
    from sg3d.cli import cli
    from sg3d.ingest.poses.estimate import PoseEstimate

    original = poses_module.estimate_sequence_poses

    def estimate_then_align(seq, start=0, stop=None, progress=None, **kw):
        given = given_poses(seq)
        if perturb_deg is not None:
            poses = perturbed(given, perturb_deg, seed)
            seq.use_poses(poses, {})
            return PoseEstimate(poses, {}, len(poses), 0, 0, 1, 0, 0.0)
        est = original(seq, start, stop, step=step, progress=progress)
        common = [i for i in sorted(est.poses) if i in given]
        T = align_trajectory(np.array([est.poses[i] for i in common]), np.array([given[i] for i in common]))
        est.poses = {i: T @ P for i, P in est.poses.items()}
        seq.use_poses(est.poses, est.unplaced)
        return est

    poses_module.estimate_sequence_poses = estimate_then_align  # type: ignore[assignment]  # swapped in for the run
    try:
        cli.main(["build", str(path), "--room", room, "--estimate-poses", *(["--quality", quality] if quality else [])],
                 standalone_mode=False, prog_name="sg3d")
    finally:
        poses_module.estimate_sequence_poses = original


def detected_frames(seq) -> tuple[list[int], float]:
    """The frames a default `sg3d build` of the whole of `seq` detects (its own frame choice,
    `choose_detected_frames`), and the seconds that choice took."""
    from sg3d.ingest.select.selection import choose_detected_frames

    t0 = time.perf_counter()
    chosen = choose_detected_frames(seq).detected
    return chosen, time.perf_counter() - t0


def jaccard(a, b) -> float:
    """|A & B| / |A | B| of two frame sets (1 when both are empty)."""
    a, b = set(a), set(b)
    return len(a & b) / len(a | b) if a | b else 1.0


def frame_set_stability(path: Path, degrees: float, seeds: int, step: int) -> dict:
    """The detected frames on the given poses, on `seeds` smooth turns of `degrees` of them and on
    the estimated poses; each set's size and Jaccard overlap with the given poses' set."""
    seq = open_sequence(path)
    given = given_poses(seq)
    base, seconds = detected_frames(seq)
    rows = {"given": (len(base), 1.0, seconds)}
    for seed in range(1, seeds + 1):
        seq = open_sequence(path)
        seq.use_poses(perturbed(given, degrees, seed), {})
        chosen, seconds = detected_frames(seq)
        rows[f"turned {degrees} deg, seed {seed}"] = (len(chosen), jaccard(base, chosen), seconds)
    seq = open_sequence(path)
    estimate_sequence_poses(seq, step=step)
    chosen, seconds = detected_frames(seq)
    rows["estimated"] = (len(chosen), jaccard(base, chosen), seconds)
    return rows


def run(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sequences", nargs="*", type=Path, default=None)
    ap.add_argument("--step", type=int, default=DEFAULT_STEP, help="odometry on every N-th frame")
    ap.add_argument("--build-room", default=None, help="also build this room on aligned estimated poses")
    ap.add_argument("--perturb-given", type=float, default=None, metavar="DEG",
                    help="with --build-room: build on the given poses turned by a smooth rotation of this "
                         "amplitude instead (no estimation), to see how the graph reacts to a pose error that size")
    ap.add_argument("--seed", type=int, default=1, help="seed of --perturb-given's rotation")
    ap.add_argument("--quality", default=None, help="with --build-room: the build's --quality preset")
    ap.add_argument("--frame-sets", action="store_true",
                    help="only compare the detected frame sets on given, turned and estimated poses (no build)")
    ap.add_argument("--seeds", type=int, default=3, help="with --frame-sets: how many turned copies of the poses")
    args = ap.parse_args(argv)
    paths = args.sequences or [p for p in DEFAULT if p.is_dir()]
    if args.frame_sets:
        print(f"load: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
        for path in paths:
            print(f"{path.name}: detected frames, Jaccard overlap with the given poses' set")
            for name, (n, overlap, seconds) in frame_set_stability(
                    path, args.perturb_given or 0.3, args.seeds, args.step).items():
                print(f"  {name:<26} {n:4d} frames  Jaccard {overlap:.3f}  (frame choice {seconds:.2f} s)")
        return
    if args.perturb_given is not None:
        if not args.build_room:
            ap.error("--perturb-given needs --build-room")
        aligned_build(paths[0], args.build_room, args.step, args.perturb_given, args.seed, args.quality)
        return
    print(f"load: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; odometry on every {args.step}th frame")
    loads = []
    for path in paths:
        r = measure(path, args.step)
        loads.append(os.getloadavg()[0])
        evo = f", evo {r['evo_ate_m']:.4f} m" if r["evo_ate_m"] is not None else ""
        print(f"{r['sequence']}: ATE {r['ate_m']:.4f} m{evo}, mean rotation error {r['rotation_error_deg']} deg, over {r['placed']} of {r['frames']} frames "
              f"({r['unplaced']} not placed), {r['loop_closures']} loop closures, {r['segments']} segments, "
              f"{r['length_m']} m travelled; {r['ms_per_input_frame']} ms per input frame "
              f"({r['cpu_ms_per_input_frame']} ms of this process's CPU time) "
              f"({r['ms_per_input_frame'] / max(r['decode_ms_per_input_frame'], 1e-9):.1f}x the "
              f"{r['decode_ms_per_input_frame']} ms of decoding its images alone)")
    print(f"load after: {', '.join(f'{v:.2f}' for v in loads)}")
    if args.build_room:
        aligned_build(paths[0], args.build_room, args.step, quality=args.quality)


if __name__ == "__main__":
    run()
