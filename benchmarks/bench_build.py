"""Whole-build benchmark: input frames/s and seconds per stage of `sg3d build` on a sequence,
for the given presets (a --method name, `:high` for --quality high), one store for all runs,
with each build's peak memory (the build process; the store runs in its own).
`--runtimes opencv,openvino` runs every preset once per detector runtime, back to back.
The one-time conversion of the OpenVINO model (into the user cache) happens before any timed build.

    python -m benchmarks.bench_build [SEQUENCE] [--methods 3d-full,3d-full:high] [--runtimes opencv,openvino]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DEFAULT_SEQ = REPO.parent / "shared" / "data" / "7scenes-redkitchen"


def run_build(seq: Path, preset: str, home: Path, runtime: str = "") -> tuple[dict, float, float]:
    """One build's --json summary, its peak resident memory in MiB and the CPU seconds it used
    (user + system, all threads: unlike wall time, barely moved by other work on the machine)."""
    env = dict(os.environ, SG3D_HOME=str(home))
    env.pop("SG3D_URI", None)
    if runtime:
        env["SG3D_DETECTOR_RUNTIME"] = runtime
    method, _, quality = preset.partition(":")
    room = f"bench-{method}-{quality or 'default'}-{runtime or 'auto'}"
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen([sys.executable, "-m", "sg3d", "build", str(seq), "--room", room,
                                 "--method", method, "--quality", quality or "default", "--json"],
                                stdout=out, stderr=err, text=True, env=env)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0), err.seek(0)
        if proc.returncode != 0:
            raise SystemExit(err.read())
        return json.loads(out.read()), usage.ru_maxrss / 1024.0, usage.ru_utime + usage.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("sequence", nargs="?", type=Path, default=DEFAULT_SEQ)
    ap.add_argument("--methods", default="3d-full,3d-full:high")
    ap.add_argument("--runtimes", default="", help="detector runtimes to compare, e.g. opencv,openvino "
                                                   "(default: the one a build picks)")
    args = ap.parse_args()
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.ingest.detect.models import SSD_MODEL_FILE, packaged_model_dir
    from sg3d.ingest.detect.openvino import converted_model, openvino_available

    if openvino_available():    # the one-time conversion, so that no timed build pays it
        converted_model(packaged_model_dir() / SSD_MODEL_FILE)
    rows = []
    with tempfile.TemporaryDirectory(prefix="sg3d-bench-") as home:
        EmbeddedServer(Path(home)).start()  # store start-up is not part of a build's time
        try:
            for method in args.methods.split(","):
                for runtime in args.runtimes.split(",") if args.runtimes else [""]:
                    rows.append((method, runtime or "auto", *run_build(args.sequence, method, Path(home), runtime)))
        finally:
            EmbeddedServer(Path(home)).stop()
    stages = sorted({k for _, _, s, _, _ in rows for k in s["seconds"]} - {"total"})
    print(f"load {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'method':<14}{'runtime':>9}{'frames':>7}{'detected':>9}{'objects':>8}{'fps':>8}{'total s':>9}{'cpu s':>7}"
          f"{'peak MiB':>9}  " + "  ".join(stages))
    from benchmarks.figures import update

    for method, runtime, s, _, _ in (rows if args.sequence == DEFAULT_SEQ else []):   # the kitchen's, quoted
        update(f"build.{method.replace(':', '_')}", {
            "runtime": runtime, "frames": s["frames"]["in_range"], "detected": s["frames"]["detected"],
            "input_frames_per_second": round(s["input_frames_per_second"], 1),
            "seconds": round(s["seconds"]["total"], 1), "load": round(os.getloadavg()[0], 1),
            "cores": os.cpu_count()})
    for method, runtime, s, peak, cpu in rows:
        print(f"{method:<14}{runtime:>9}{s['frames']['in_range']:>7}{s['frames']['detected']:>9}{s['graph']['room_objects']:>8}"
              f"{s['input_frames_per_second']:>8.1f}{s['seconds']['total']:>9.2f}{cpu:>7.1f}{peak:>9.0f}  "
              + "  ".join(f"{s['seconds'].get(k, 0.0):.2f}" for k in stages))


if __name__ == "__main__":
    main()
