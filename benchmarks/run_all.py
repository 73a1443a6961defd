"""Every benchmark in one run, one section each, then a summary table.

    python -m benchmarks.run_all [--quick]

--quick uses smaller stores (fewer objects) so the whole run takes a few minutes on 2 cores.
The build's peak memory is the largest resident set of the `sg3d build` child processes
(getrusage), i.e. of a 3d-full build of the kitchen.
"""
from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time

STEPS = [
    ("frames: read + ABIR + KGE vs decode floor", ["benchmarks/bench_frames.py", "--repeat", "1"], None),
    ("build: whole pipeline per preset", ["-m", "benchmarks.bench_build", "--methods", "3d-full"], None),
    ("detect: OpenCV DNN vs OpenVINO, frame by frame", ["-m", "benchmarks.bench_detect"], ["--frames", "30"]),
    ("store: upserts and merge latency", ["-m", "benchmarks.bench_store"], ["--objects", "2000", "--single", "50", "--graphs", "10"]),
    ("store: reference size, 1,000 rooms", ["-m", "benchmarks.bench_store", "--objects", "100000", "--rooms", "1000"],
     ["--objects", "10000", "--rooms", "100", "--single", "50", "--graphs", "10"]),
    ("ask: latency on a generated store", ["-m", "benchmarks.bench_ask"], ["--objects", "20000", "--rooms", "200", "--repeat", "10"]),
]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    summary = []
    for title, cmd, quick in STEPS:
        full = [sys.executable, *cmd, *((quick or []) if args.quick else [])]
        print(f"\n== {title}\n$ {' '.join(full[1:])}", flush=True)
        t0 = time.perf_counter()
        out = subprocess.run(full, capture_output=True, text=True)
        print(out.stdout.rstrip())
        if out.returncode != 0:
            print(out.stderr.strip().splitlines()[-1] if out.stderr.strip() else f"exit {out.returncode}")
        summary.append((title, "ok" if out.returncode == 0 else "failed", time.perf_counter() - t0))
    peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"\n{'benchmark':<48}{'status':>8}{'seconds':>10}")
    for title, status, seconds in summary:
        print(f"{title:<48}{status:>8}{seconds:>10.1f}")
    print(f"{'peak resident memory of any child (build, store)':<48}{'':>8}{peak_mb:>8.0f} MB")


if __name__ == "__main__":
    main()
