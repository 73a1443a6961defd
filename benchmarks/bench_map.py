"""`sg3d map` against a camera's rate: a writer process writes a recorded room into a folder at 30
frames/s while `sg3d map` follows it and `sg3d serve` answers questions from the growing graph.

    python -m benchmarks.bench_map                        # the kitchen, 30 frames/s, 100 asks
    python -m benchmarks.bench_map --room-dir DIR --fps 30 --asks 0 --stop 300
    python -m benchmarks.bench_map --realtime --no-poses [--load 1] [--realsense]   # see map_noposes

Prints: when the first objects were visible (after the first frame was written), the latency
frame written -> its evidence visible in the store (p50, p95, max), frames skipped while behind,
backlog at the end, peak memory of the map process, publish and discovery times; with --asks,
N room-scoped `POST /ask` spread over the mapping (errors, distinct answers, p50/p95 ms); with
--compare, the end-of-source graph against `sg3d build` of the same frames (labels, positions,
relations). Everything runs in a scratch store; each process is the real command.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path
from typing import Any

import httpx

from benchmarks.bench_serve import start_server

REPO = Path(__file__).resolve().parents[1]
KITCHEN = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared")) / "data" / "7scenes-redkitchen"
QUESTIONS = ["how many objects are there?", "how many cups are there?", "is there a sink?",
             "what is on the counter?", "how many chairs are there?"]


def _asker(url: str, token: str, room: str, n: int, every: float, out: dict, stop: threading.Event) -> None:
    with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=30) as c:
        for k in range(n):
            if stop.is_set():
                break
            q = QUESTIONS[k % len(QUESTIONS)]
            t0 = time.perf_counter()
            try:
                r = c.post("/ask", json={"question": q, "room": room})
                ok = r.status_code == 200
                text = r.json().get("answer", r.text) if ok else r.text
            except httpx.HTTPError as exc:
                ok, text = False, str(exc)
            out["ms"].append((time.perf_counter() - t0) * 1000)
            out["errors"] += 0 if ok else 1
            out["answers"][q].add(str(text))
            time.sleep(every)


def _wait_until_mapping(home: Path, mapper: subprocess.Popen, timeout: float = 120) -> None:
    """Until the map process has announced its room (it follows the folder from then on)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        out = subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), "rooms", "--json"],
                             capture_output=True, text=True)
        if out.returncode == 0 and '"live"' in out.stdout:
            return
        if mapper.poll() is not None:
            raise SystemExit("sg3d map exited before the first frame")
        time.sleep(0.5)
    raise SystemExit("sg3d map did not start")


def _graph(home: Path, room: str) -> dict:
    out = subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), "export", "--room", room, "--out", "-"],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def compare(home: Path, mapped: str, built: str) -> dict:
    """Labels, named positions and relations of two rooms of one store."""
    a, b = _graph(home, mapped), _graph(home, built)
    la, lb = Counter(n["label"] for n in a["nodes"]), Counter(n["label"] for n in b["nodes"])
    moved = []
    for n in b["nodes"]:
        same = [m for m in a["nodes"] if m["label"] == n["label"]]
        if same and n["layer"] != "structure":
            moved.append(min(sum((m[k] - n[k]) ** 2 for k in "xyz") ** 0.5 for m in same))
    return {"same_labels": la == lb, "labels_only_mapped": dict(la - lb), "labels_only_built": dict(lb - la),
            "max_position_gap_m": round(max(moved), 4) if moved else None,
            "relations": [len(a["edges"]), len(b["edges"])]}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--room-dir", type=Path, default=KITCHEN)
    ap.add_argument("--fps", type=float, default=30.0)
    ap.add_argument("--stop", type=int, default=None, help="write only the first N frames")
    ap.add_argument("--asks", type=int, default=100)
    ap.add_argument("--compare", action="store_true", help="also build the same frames and compare")
    ap.add_argument("--port", type=int, default=18777)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--realtime", action="store_true", help="play at the recording's own rate (30 frames/s)")
    ap.add_argument("--no-poses", action="store_true",
                    help="a camera without poses: kitchen and living room, tracked live (benchmarks.map_noposes)")
    ap.add_argument("--rooms", default="kitchen,living", help="with --no-poses: which rooms")
    ap.add_argument("--load", type=int, default=0, help="with --no-poses: processes keeping a core busy each")
    ap.add_argument("--realsense", action="store_true", help="with --no-poses: also through a RealSense recording")
    a = ap.parse_args(argv)
    if a.no_poses:
        from benchmarks.map_noposes import main as no_poses

        no_poses(a.rooms.split(","), a.load, a.realsense, a.json)
        return
    with tempfile.TemporaryDirectory(prefix="sg3d-bench-map-") as tmp:
        home, folder = Path(tmp) / "home", Path(tmp) / "frames"
        folder.mkdir()
        subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), "db", "start"], check=True,
                       capture_output=True)
        server = start_server(home, a.port) if a.asks else None
        mapper = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(home), "map", str(folder), "--room", "live",
                                   "--stop-when-idle", "3", "--json"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                  text=True)
        _wait_until_mapping(home, mapper)     # the map process is up and following the folder
        writer_cmd = [sys.executable, "-m", "benchmarks.live_writer", str(a.room_dir), str(folder), "--fps", str(a.fps)]
        if a.stop:
            writer_cmd += ["--stop", str(a.stop)]
        asked: dict[str, Any] = {"ms": [], "errors": 0, "answers": {q: set() for q in QUESTIONS}}
        stop = threading.Event()
        t_write = time.monotonic()
        writer = subprocess.Popen(writer_cmd, cwd=REPO)
        asker = None
        if server is not None:
            from sg3d.server.auth import token_path

            token = token_path(home).read_text().strip()
            n_frames = a.stop or len(list(a.room_dir.glob("frame-*.color.*"))) or len(list((a.room_dir / "image").glob("*")))
            every = max(0.01, n_frames / a.fps / a.asks)
            asker = threading.Thread(target=_asker, args=(f"http://127.0.0.1:{a.port}", token, "live", a.asks, every,
                                                          asked, stop), daemon=True)
            asker.start()
        writer.wait()
        written_s = time.monotonic() - t_write
        out, _ = mapper.communicate()
        stop.set()
        if asker is not None:
            asker.join()
        if server is not None:
            server.terminate()
            server.wait()
        summary = json.loads(out)
        report = {"frames_written": summary["frames"]["received"], "writing_s": round(written_s, 2),
                  "first_objects_after_s": summary["first_objects_after_s"], "latency_s": summary["latency_s"],
                  "skipped_behind": summary["frames"]["skipped_behind"], "jumped": summary["frames"]["jumped"], "detected_live": summary["frames"]["detected"]
                  - summary["frames"]["detected_at_end"], "detected_at_end": summary["frames"]["detected_at_end"],
                  "backlog_at_end": summary["backlog_at_end"], "peak_memory_mib": summary["peak_memory_mib"],
                  "objects": summary["objects"], "relations": summary["relations"], "publishes": summary["publishes"],
                  "seconds": summary["seconds"]}
        if a.asks:
            ms = sorted(asked["ms"])
            report["asks"] = {"n": len(ms), "errors": asked["errors"],
                              "distinct_answers": {q: len(v) for q, v in asked["answers"].items()},
                              "p50_ms": round(statistics.median(ms), 1) if ms else None,
                              "p95_ms": round(ms[int(0.95 * (len(ms) - 1))], 1) if ms else None}
        if a.compare:
            subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), "build", str(folder), "--room", "built",
                            "--json"], check=True, capture_output=True)
            report["against_build"] = compare(home, "live", "built")
        subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), "db", "stop"], capture_output=True)
    if a.json:
        print(json.dumps(report))
        return
    for k, v in report.items():
        print(f"{k:>22}: {v}")


if __name__ == "__main__":
    main()
