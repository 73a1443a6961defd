"""python -m benchmarks.synth --kind desk --seed 3 --out DIR"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from benchmarks.synth import KINDS, generate


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.synth", description="render a generated room with exact ground truth")
    ap.add_argument("--kind", choices=KINDS, default="room")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--frames", type=int, default=None, help="frames (default 80; an apartment's walk sets its own)")
    ap.add_argument("--size", default="320x240", help="WIDTHxHEIGHT of the frames")
    args = ap.parse_args(argv)
    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        ap.error(f"--size wants WIDTHxHEIGHT, got {args.size!r}")
    try:
        gt = generate(args.kind, args.seed, args.out, args.frames, width, height)
    except ImportError as exc:
        print(f"error: the generator needs open3d (pip install 'sg3d[synth]'): {exc}", file=sys.stderr)
        return 2
    seen = sum(o["seen"] for o in gt["objects"])
    print(f"{args.out}: {gt['frames']} frames, {seen} of {len(gt['objects'])} objects seen, "
          f"floor {'seen' if gt['structure']['floor']['seen'] else 'not seen'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
