"""Windows from one walk: generated apartments with windows (benchmarks.synth, kind apartment)
through the pipeline as `sg3d build --rooms auto` runs it (detection, discovery with windows,
`sg3d.ingest.discover.windows`), judged against the generator's exact windows; and the real
recordings of ../shared/data, where every window found is counted (none has a located window in
its ground truth: what is found there is listed, to be looked at).

    python -m benchmarks.bench_windows [--n 4] [--first-seed 0] [--real] [--json]

A true window is found when a window node's middle lies within MATCH_M of its middle (world
frame); a window node matching no true window is false.
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

MATCH_M = 0.6
REPO = Path(__file__).resolve().parents[1]
REAL = ("open3d-livingroom1-micro", "7scenes-redkitchen", "3dmatch-studyroom/fragment-1", "3dmatch-studyroom/fragment-2")


def windows_of(folder: Path) -> list[dict]:
    """The window nodes a walk build of `folder` makes (one chunk per 3000 frames, as a build)."""
    from sg3d.app.build import check_detector
    from sg3d.app.places import walk_settings
    from sg3d.ingest.pipeline import BuildPipeline, Settings, Target, chunk_ranges
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames
    from sg3d.ingest.readers import open_sequence
    from sg3d.core.geometry import Ground

    settings = walk_settings(Settings(), "auto")
    seq = open_sequence(folder)
    g = estimate_gravity(sample_frames(seq, 20, 0, len(seq)))
    detector = check_detector(settings)
    pipeline = BuildPipeline(settings, detector)
    out = []
    for a, b in chunk_ranges(0, len(seq), settings.chunk_frames):
        graph = pipeline.run(seq, (a, b), Ground(g.up, g.floor_height), Target("walk", "bench"))
        out += [{"middle": [round(float(v), 3) for v in o.mean], "size": [round(float(v), 2) for v in o.size]}
                for o in graph.objects if o.label == "window"]
    return out


def judge(gt: dict, found: list[dict]) -> dict:
    """Each true window found or not (nearest window node within MATCH_M), the false ones."""
    truth = gt["apartment"]["windows"]
    used: set[int] = set()
    missed = []
    for w in truth:
        d = [np.linalg.norm(np.subtract(f["middle"], w["position_world"])) for f in found]
        k = int(np.argmin(d)) if d else -1
        if k >= 0 and d[k] <= MATCH_M and k not in used:
            used.add(k)
        else:
            missed.append(f"{w['id']} in {w['room']} ({w['width']:.2f} m wide, sill {w['sill']:.2f}, "
                          f"top {w['top']:.2f})")
    return {"windows": len(truth), "found": len(used), "false": len(found) - len(used), "missed": missed}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=4)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--real", action="store_true", help="also the real recordings of ../shared/data")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    from benchmarks.synth import generate

    rows = []
    with tempfile.TemporaryDirectory(prefix="sg3d-windows-") as tmp:
        for seed in range(args.first_seed, args.first_seed + args.n):
            t0 = time.perf_counter()
            gt = generate("apartment", seed, Path(tmp) / f"apartment-{seed}")
            row = {"seed": seed, **judge(gt, windows_of(Path(tmp) / f"apartment-{seed}")),
                   "seconds": round(time.perf_counter() - t0, 1)}
            rows.append(row)
            print(f"seed {seed}: {row['found']}/{row['windows']} found, {row['false']} false "
                  f"({row['seconds']} s); missed: {'; '.join(row['missed']) or '-'}", file=sys.stderr)
    real = {}
    for name in REAL if args.real else ():
        if (REPO.parent / "shared" / "data" / name).exists():
            real[name] = windows_of(REPO.parent / "shared" / "data" / name)
            print(f"{name}: {len(real[name])} windows {real[name]}", file=sys.stderr)
    total = {k: sum(r[k] for r in rows) for k in ("windows", "found", "false")}
    if args.json:
        print(json.dumps({"apartments": rows, "total": total, "real": real}, indent=1))
    else:
        print(f"apartments {len(rows)}: {total['found']}/{total['windows']} windows found, {total['false']} false; "
              + "real: " + ", ".join(f"{k} {len(v)}" for k, v in real.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
