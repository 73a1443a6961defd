"""Whole-build benchmark: input frames/s and seconds per stage of `sg3d build` on a sequence,
for the given presets (a --method name, `:high` for --quality high), one store for all runs.

    python -m benchmarks.bench_build [SEQUENCE] [--methods 3d-full,3d-full:high]
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


def run_build(seq: Path, preset: str, home: Path) -> dict:
    env = dict(os.environ, SG3D_HOME=str(home))
    env.pop("SG3D_URI", None)
    method, _, quality = preset.partition(":")
    out = subprocess.run([sys.executable, "-m", "sg3d", "build", str(seq), "--room", f"bench-{method}-{quality or 'default'}",
                          "--method", method, "--quality", quality or "default", "--json"],
                         capture_output=True, text=True, env=env)
    if out.returncode != 0:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("sequence", nargs="?", type=Path, default=DEFAULT_SEQ)
    ap.add_argument("--methods", default="3d-full,3d-full:high")
    args = ap.parse_args()
    from graphdb.embedded import EmbeddedServer

    rows = []
    with tempfile.TemporaryDirectory(prefix="sg3d-bench-") as home:
        EmbeddedServer(Path(home)).start()  # store start-up is not part of a build's time
        try:
            for method in args.methods.split(","):
                rows.append((method, run_build(args.sequence, method, Path(home))))
        finally:
            EmbeddedServer(Path(home)).stop()
    stages = sorted({k for _, s in rows for k in s["seconds"]} - {"total"})
    print(f"{'method':<14}{'frames':>7}{'detected':>9}{'objects':>8}{'fps':>8}{'total s':>9}  " + "  ".join(stages))
    for method, s in rows:
        print(f"{method:<14}{s['frames']['in_range']:>7}{s['frames']['detected']:>9}{s['graph']['room_objects']:>8}"
              f"{s['input_frames_per_second']:>8.1f}{s['seconds']['total']:>9.2f}  "
              + "  ".join(f"{s['seconds'].get(k, 0.0):.2f}" for k in stages))


if __name__ == "__main__":
    main()
