"""Milliseconds per detection of colour naming on real frames: the light on the object, the naming.

    python benchmarks/bench_colour.py [SEQUENCE] [--frames 20] [--boxes 10] [--repeat 3]

SEQUENCE defaults to ../shared/data/7scenes-redkitchen beside the repository. On --frames frames
spread over the sequence, --boxes boxes of 40 to 250 pixels a side (a fixed random draw) stand
for detections; each one's own pixels are taken as the pipeline takes them
(`sg3d.ingest.objects.attributes.colour_pixels`), then timed: `sg3d.ingest.objects.colour.surround_cast` (the cast and
white reference of the light on the object) and `sg3d.ingest.objects.colour.read_colour` (the naming). Each
figure is the best of --repeat passes after one warm-up pass (which also builds the survey table).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import numpy as np  # noqa: E402

from sg3d.ingest.objects import colour  # noqa: E402
from sg3d.ingest.objects.attributes import clip_box, colour_pixels  # noqa: E402
from sg3d.ingest.readers import open_sequence  # noqa: E402

DEFAULT = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared")) / "data" / "7scenes-redkitchen"


def detections(seq, n_frames: int, n_boxes: int):
    """(frame, bounds, pixels) of n_boxes random boxes on each of n_frames frames."""
    rng = np.random.default_rng(0)
    out = []
    for i in np.linspace(0, len(seq) - 1, n_frames).round().astype(int):
        frame = seq.frame(int(i))
        w, h = frame.size
        for _ in range(n_boxes):
            bw, bh = rng.integers(40, 251, 2)
            x, y = rng.integers(0, max(1, w - bw)), rng.integers(0, max(1, h - bh))
            bounds = clip_box((x, y, x + bw, y + bh), w, h)
            out.append((frame, bounds, colour_pixels(frame, bounds)[0]))
    return out


def best_ms(fn, items, repeat: int) -> float:
    fn(items)
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn(items)
        best = min(best, time.perf_counter() - t0)
    return 1000.0 * best / len(items)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sequence", nargs="?", default=str(DEFAULT))
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--boxes", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    if not Path(args.sequence).is_dir():
        print(f"sequence not found: {args.sequence}", file=sys.stderr)
        return 2
    items = detections(open_sequence(args.sequence), args.frames, args.boxes)
    casts = [colour.surround_cast(f.color, b) for f, b, _ in items]
    cast_ms = best_ms(lambda xs: [colour.surround_cast(f.color, b) for f, b, _ in xs], items, args.repeat)
    name_ms = best_ms(lambda xs: [colour.read_colour(p, c) for (_, _, p), c in zip(xs, casts)], items, args.repeat)
    pixels = int(np.median([len(p) for _, _, p in items]))
    print(f"{len(items)} detections (median {pixels} pixels each): light on the object {cast_ms:.3f} ms, "
          f"naming {name_ms:.3f} ms, together {cast_ms + name_ms:.3f} ms per detection")
    return 0


if __name__ == "__main__":
    sys.exit(main())
