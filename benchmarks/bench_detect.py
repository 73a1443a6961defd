"""Detector runtimes side by side: ms per frame of the packaged SSD through OpenCV DNN and through
OpenVINO on the same frames in one process (frame by frame, alternating, so a busy machine slows
both alike), and how far their detections differ.

    python -m benchmarks.bench_detect [SEQUENCE] [--frames 100] [--threads N]
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import cv2
import numpy as np

REPO = Path(__file__).resolve().parents[1]
DEFAULT_SEQ = REPO.parent / "shared" / "data" / "7scenes-redkitchen"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("sequence", nargs="?", type=Path, default=DEFAULT_SEQ)
    ap.add_argument("--frames", type=int, default=100, help="frames spread evenly over the sequence")
    ap.add_argument("--threads", type=int, default=None, help="inference threads (default: every core)")
    args = ap.parse_args()
    from sg3d.ingest.detect.models import SsdMobilenetDetector
    from sg3d.ingest.detect.openvino import OpenVinoSsdDetector
    from sg3d.ingest.readers import open_sequence

    seq = open_sequence(args.sequence)
    picks = np.linspace(0, len(seq) - 1, min(args.frames, len(seq))).astype(int)
    runtimes = {"opencv": SsdMobilenetDetector(num_threads=args.threads),
                "openvino": OpenVinoSsdDetector(num_threads=args.threads)}
    for det in runtimes.values():
        det.prepare()
    seconds = dict.fromkeys(runtimes, 0.0)
    worst_score = worst_box = 0.0
    label_differences = detections = 0
    for i in picks:
        image = seq.frame(int(i)).color
        found = {}
        for name, det in runtimes.items():
            t0 = time.perf_counter()
            found[name] = det.detect(image)
            seconds[name] += time.perf_counter() - t0
        a, b = found["opencv"], found["openvino"]
        detections += len(a)
        if [d.labels for d in a] != [d.labels for d in b]:
            label_differences += 1
            continue
        for x, y in zip(a, b):
            worst_score = max(worst_score, float(np.abs(np.subtract(x.scores, y.scores)).max()))
            worst_box = max(worst_box, float(np.abs(np.subtract(x.box, y.box)).max()))
    n = len(picks)
    load = os.getloadavg()[0]
    print(f"{n} frames, {detections} detections, load {load:.1f} on {os.cpu_count()} cores, "
          f"{cv2.getNumThreads()} OpenCV threads")
    for name in runtimes:
        print(f"{name:<9}{seconds[name] / n * 1e3:8.1f} ms/frame")
    print(f"speed-up {seconds['opencv'] / seconds['openvino']:.2f}x; frames whose labels differ: {label_differences}; "
          f"worst score difference {worst_score:.2g}, worst box difference {worst_box:.2g} px")


if __name__ == "__main__":
    main()
