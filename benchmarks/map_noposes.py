"""`python -m benchmarks.bench_map --realtime --no-poses [--load N] [--rooms kitchen,living] [--realsense]`:
a camera that gives no poses, played at its own frame rate (30 frames/s) while `sg3d map` tracks
and maps it, each room in a scratch store:

- through a folder: `benchmarks.live_writer --no-poses` writes the frames without pose files;
- with `--realsense`, also through the RealSense source: the frames recorded first into a .db3 by
  librealsense's own recorder (pyrealsense2's software device: `benchmarks.realsense_recording`), then played back by `sg3d map realsense:FILE` at the recorded rate.

Per room and source it reports (one JSON line per room on stderr as it ends, then one table on
stdout with the load of each row; `--json`: the reports as one list): first objects after the first frame (s), latency p50/p95 (s),
tracking (frames tracked / skipped, lost, restarts, longest time without a pose, ms per frame),
ATE RMSE of the live trajectory (`--trajectory-out`) against the recording's given poses (evo's
APE when evo is installed, and the project's `ate_rmse`), per-stage counts, and the end graph's
any-label recall against the room's ground truth next to the offline pose-free build of the same
frames (`sg3d build` of the folder; each graph is brought into the ground truth's frame by the
Umeyama alignment of its own trajectory to the given poses). `--load N` keeps N extra processes
spinning (one core each) while the map runs; the machine's load average is printed with it.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional

import numpy as np

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared"))
ROOMS = {
    "kitchen": (SHARED / "data" / "7scenes-redkitchen", SHARED / "eval" / "kitchen_gt.json"),
    "living": (SHARED / "data" / "open3d-livingroom1-micro", REPO / "benchmarks" / "rooms" / "livingroom_gt.json"),
}
BURN = "while True: pass"


def _sg3d(home: Path, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), *args], capture_output=True, text=True,
                          check=check)


def given_by_number(src: Path) -> dict[int, np.ndarray]:
    """The recording's given poses by frame number (timestamp x 30, as its reader numbers them)."""
    from sg3d.ingest.readers import open_sequence

    seq = open_sequence(src)
    out = {}
    for i in range(len(seq)):
        try:
            out[round(seq.timestamp_of(i) * 30)] = seq.frame(i, lazy=True).pose
        except Exception:      # a frame without a usable given pose is not compared
            continue
    return out


def trajectory_against(tum: Path, given: dict[int, np.ndarray]) -> dict:
    """ATE of a TUM trajectory (times x 30 = frame numbers) against the given poses, and the 4x4
    alignment that maps the trajectory's world onto the given one."""
    from benchmarks.bench_poses import evo_ate
    from sg3d.ingest.poses.trajectory import align_trajectory, ate_rmse, read_tum

    if not tum.is_file() or tum.stat().st_size == 0:
        return {"ate_m": None, "evo_ate_m": None, "poses": 0, "align": None}
    times, poses = read_tum(tum)
    pairs = [(T, given[round(t * 30)]) for t, T in zip(times, poses) if round(t * 30) in given]
    if len(pairs) < 3:
        return {"ate_m": None, "evo_ate_m": None, "poses": len(pairs), "align": None}
    E, G = np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])
    evo = evo_ate(E, G)
    return {"ate_m": round(ate_rmse(E, G), 4), "evo_ate_m": round(evo, 4) if evo is not None else None,
            "poses": len(pairs), "align": align_trajectory(E, G)}


def any_label_recall(home: Path, room: str, gt_path: Path, align: Optional[np.ndarray]) -> Optional[float]:
    """Any-label recall (`sg3d.evaluation.evaluate.object_metrics`) of ROOM's graph, its positions
    moved by `align` into the ground truth's frame."""
    from sg3d.evaluation.evaluate import DEFAULT_TOLERANCE, object_metrics
    from sg3d.evaluation.ground_truth import load_gt
    from sg3d.evaluation.matching import Node

    if align is None:
        return None
    out = _sg3d(home, "export", "--room", room, "--out", "-")
    nodes = []
    for n in json.loads(out.stdout)["nodes"]:
        if n.get("x") is None:
            continue
        p = align[:3, :3] @ np.array([n["x"], n["y"], n["z"]], float) + align[:3, 3]
        nodes.append(Node(n["id"], n.get("label") or "", (float(p[0]), float(p[1]), float(p[2])), None, None,
                          n.get("layer") or "object"))
    recall = object_metrics(load_gt(gt_path), nodes, DEFAULT_TOLERANCE)["recall"]
    return round(recall, 3) if recall is not None else None


def _burners(n: int) -> list[subprocess.Popen]:
    return [subprocess.Popen([sys.executable, "-c", BURN]) for _ in range(n)]


def _stop(procs: list[subprocess.Popen]) -> None:
    for p in procs:
        p.terminate()
        p.wait()


def map_live(home: Path, source: str, room: str, traj: Path, writer_cmd: Optional[list[str]], load: int) -> dict:
    """Run `sg3d map SOURCE` (and the writer, for a folder) with `load` burners; the summary."""
    from benchmarks.bench_map import _wait_until_mapping

    burners = _burners(load)
    try:
        mapper = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(home), "map", source, "--room", room,
                                   "--stop-when-idle", "3", "--trajectory-out", str(traj), "--json"],
                                  stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        writer = None
        if writer_cmd is not None:
            _wait_until_mapping(home, mapper)
            writer = subprocess.Popen(writer_cmd, cwd=REPO)
        loads = []
        while mapper.poll() is None:
            loads.append(os.getloadavg()[0])
            time.sleep(1.0)
        if writer is not None:
            writer.wait()
        out, _ = mapper.communicate()
    finally:
        _stop(burners)
    summary = json.loads(out)
    summary["load_avg"] = round(float(np.mean(loads)), 2) if loads else None
    return summary


def _row(summary: dict, traj: dict) -> dict:
    t = summary.get("tracking") or {}
    return {"frames": summary["frames"]["received"], "first_objects_after_s": summary["first_objects_after_s"],
            "latency_p50_s": summary["latency_s"].get("p50"), "latency_p95_s": summary["latency_s"].get("p95"),
            "tracked": t.get("ran"), "tracking_skipped": t.get("skipped"), "lost": t.get("lost"),
            "restarts": t.get("restarts"), "longest_loss_s": t.get("longest_loss_s"),
            "loop_closures": t.get("loop_closures"),
            "loop_keyframes": t.get("loop_keyframes"),
            "track_ms_mean": t.get("ms_mean"), "track_ms_p95": t.get("ms_p95"),
            "ate_m": traj["ate_m"], "evo_ate_m": traj["evo_ate_m"], "ate_poses": traj["poses"],
            "objects": summary["objects"], "stages": summary.get("stages"), "load_avg": summary.get("load_avg")}


def realsense_recording(src: Path, path: Path) -> tuple[Optional[Path], str]:
    """SRC's frames recorded by librealsense's recorder (a .db3 from 2.57 on), or (None, why not)."""
    try:
        from benchmarks.realsense_recording import record_realsense

        n = len(given_by_number(src))
        return record_realsense(path, src, n, fps=30), ""
    except Exception as exc:      # noqa: BLE001 - why not, in the report (no pyrealsense2, no libusb, ...)
        return None, f"{type(exc).__name__}: {exc}"


def run_room(name: str, load: int, realsense: bool) -> dict:
    src, gt = ROOMS[name]
    given = given_by_number(src)
    report: dict = {"room": name, "load": load}
    with tempfile.TemporaryDirectory(prefix="sg3d-bench-noposes-") as tmp:
        home, folder = Path(tmp) / "home", Path(tmp) / "frames"
        folder.mkdir()
        _sg3d(home, "db", "start")
        writer = [sys.executable, "-m", "benchmarks.live_writer", str(src), str(folder), "--fps", "30", "--no-poses"]
        live = map_live(home, str(folder), "live", Path(tmp) / "live.tum", writer, load)
        live_traj = trajectory_against(Path(tmp) / "live.tum", given)
        report["folder"] = _row(live, live_traj)
        if realsense:
            db3, why = realsense_recording(src, Path(tmp) / f"{name}.db3")
            if db3 is None:
                report["realsense"] = {"not_run": why}
            else:
                rs = map_live(home, f"realsense:{db3}", "live-rs", Path(tmp) / "rs.tum", None, load)
                rs_traj = trajectory_against(Path(tmp) / "rs.tum", given)
                report["realsense"] = _row(rs, rs_traj)
                report["realsense"]["recall_any_label"] = any_label_recall(home, "live-rs", gt, rs_traj["align"])
        _sg3d(home, "build", str(folder), "--room", "built", "--trajectory-out", str(Path(tmp) / "built.tum"), "--json")
        built_traj = trajectory_against(Path(tmp) / "built.tum", given)
        report["folder"]["recall_any_label"] = any_label_recall(home, "live", gt, live_traj["align"])
        report["offline_build"] = {"ate_m": built_traj["ate_m"],
                                   "recall_any_label": any_label_recall(home, "built", gt, built_traj["align"])}
        _sg3d(home, "db", "stop", check=False)
    return report


TABLE_HEAD = ("| room | source | --load | load avg | first objects | latency p95 | tracked / lost / restarts "
              "| longest loss | loop closures | ATE live | ATE offline | recall live / offline |")


def _cell(v, unit: str = "", scale: float = 1.0, digits: int = 2) -> str:
    return "-" if v is None else f"{v * scale:.{digits}f}{unit}"


def table(reports: list[dict]) -> str:
    """One markdown row per room and source: the figures the issue asks for, with the load."""
    rows = [TABLE_HEAD, "|" + "---|" * (TABLE_HEAD.count("|") - 1)]
    for r in reports:
        built = r.get("offline_build", {})
        for source in ("folder", "realsense"):
            row = r.get(source)
            if row is None:
                continue
            if "not_run" in row:
                rows.append(f"| {r['room']} | {source} | {r['load']} | not run: {row['not_run']} |")
                continue
            rows.append(
                f"| {r['room']} | {source} | {r['load']} | {_cell(row.get('load_avg'), digits=1)} "
                f"| {_cell(row['first_objects_after_s'], ' s')} | {_cell(row['latency_p95_s'], ' s')} "
                f"| {row['tracked']} / {row['lost']} / {row['restarts']} | {_cell(row['longest_loss_s'], ' s')} "
                f"| {row.get('loop_closures')} | {_cell(row['ate_m'], ' cm', 100, 1)} "
                f"| {_cell(built.get('ate_m'), ' cm', 100, 1)} "
                f"| {_cell(row.get('recall_any_label'))} / {_cell(built.get('recall_any_label'))} |")
    return "\n".join(rows)


def main(rooms: list[str], load: int, realsense: bool, as_json: bool) -> None:
    """Each room in turn (its JSON line on stderr as it ends), then one table on stdout (or, with
    `as_json`, the reports as one JSON list)."""
    reports = []
    for name in rooms:
        r = run_room(name, load, realsense)
        reports.append(r)
        print(json.dumps(r), file=sys.stderr, flush=True)
    print(json.dumps(reports) if as_json else table(reports))
