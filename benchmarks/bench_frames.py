"""Frames/s of reading + ABIR + KGE over a sequence, next to the plain decode floor.

    python benchmarks/bench_frames.py [SEQUENCE] [--repeat 3]

SEQUENCE defaults to ../shared/data/7scenes-redkitchen beside the repository. The floor is
cv2.imread of every colour image and depth image (what any reader must at least do); the
pipeline figure is `FrameSelector` over the same frames (lazy frames: grey decode for ABIR,
full colour + depth only for keyframes and anchors). Each figure is the best of --repeat runs
after one warm-up pass, so the OS file cache is warm for both.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import cv2  # noqa: E402

from sg3d.ingest.readers import open_sequence  # noqa: E402
from sg3d.ingest.select.abir import ABIR  # noqa: E402
from sg3d.ingest.select.kge import KeyframeGrouper  # noqa: E402
from sg3d.ingest.select.selection import FrameSelector  # noqa: E402

DEFAULT = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared")) / "data" / "7scenes-redkitchen"


def decode_floor(seq) -> float:
    t0 = time.perf_counter()
    for entry in seq._entries:
        cv2.imread(str(entry.color), cv2.IMREAD_COLOR)
        cv2.imread(str(entry.depth), cv2.IMREAD_UNCHANGED)
    return time.perf_counter() - t0


def eager_read(seq) -> float:
    t0 = time.perf_counter()
    for _ in seq.frames():
        pass
    return time.perf_counter() - t0


def pipeline(seq):
    selector = FrameSelector(ABIR(), KeyframeGrouper())
    t0 = time.perf_counter()
    for _ in selector.groups(seq):
        pass
    return time.perf_counter() - t0, selector.stats


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sequence", nargs="?", default=str(DEFAULT))
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    if not Path(args.sequence).is_dir():
        print(f"sequence not found: {args.sequence} (set SG3D_SHARED or pass a folder)", file=sys.stderr)
        return 2
    seq = open_sequence(args.sequence)
    n = len(seq)
    print(f"{args.sequence}: {n} frames {seq.image_size[0]}x{seq.image_size[1]}, "
          f"OpenCV threads {cv2.getNumThreads()}, CPUs {os.cpu_count()}")
    decode_floor(seq)  # warm the file cache
    floor = min(decode_floor(seq) for _ in range(args.repeat))
    eager = min(eager_read(seq) for _ in range(args.repeat))
    runs = [pipeline(seq) for _ in range(args.repeat)]
    best, stats = min(runs, key=lambda r: r[0])
    print(f"  decode floor (imread colour + depth)    {floor:6.2f} s  {n / floor:7.1f} frames/s")
    print(f"  eager read (Frame: colour + reg. depth)  {eager:6.2f} s  {n / eager:7.1f} frames/s"
          f"  ({eager / floor:.2f}x floor)")
    print(f"  read + ABIR + KGE (lazy frames)          {best:6.2f} s  {n / best:7.1f} frames/s"
          f"  ({best / floor:.2f}x floor; aim <= 2x)")
    print(f"  blurry {stats.blurry}, keyframes {stats.keyframes}, anchors {stats.anchors}, groups {stats.groups}, "
          f"kept {stats.kept}/{stats.read} = {100 * stats.fraction_kept:.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
