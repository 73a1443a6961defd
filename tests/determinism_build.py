"""One build's local graph, written as JSON for tests/e2e/test_determinism.py (run in a process of its
own, so the thread and instruction-set settings in its environment apply to every library):

    python -m tests.determinism_build SEQUENCE STOP THREADS OUT.json

The graph is the pipeline's output (`BuildPipeline.run`), every float kept whole; `raw` is a digest of the
detector network's raw outputs on the first frame, which tells whether its kernels changed."""
from __future__ import annotations

import hashlib
import json
import sys

import numpy as np


def _raw_digest(detector, image) -> str:
    """SHA-1 of the OpenVINO network's outputs on one image ('' for another runtime)."""
    request = getattr(detector, "_request", None)
    if request is None:
        return ""
    import cv2

    from sg3d.ingest.detect.models import SSD_INPUT_SIZE

    out = request.infer({0: cv2.cvtColor(cv2.resize(image, SSD_INPUT_SIZE), cv2.COLOR_BGR2RGB)[None]})
    return hashlib.sha1(b"".join(np.ascontiguousarray(v).tobytes() for v in out.values())).hexdigest()


def build(sequence: str, stop: int, threads: int) -> dict:
    from sg3d.ingest.detect.choice import detector_for
    from sg3d.ingest.config import BuildConfig
    from sg3d.ingest.pipeline import BuildPipeline, Target
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames
    from sg3d.ingest.readers import open_sequence
    from sg3d.ingest.stages import Ground

    seq = open_sequence(sequence, None)
    stop = min(stop, len(seq))
    settings = BuildConfig()
    detector = detector_for(settings.detect.detector, settings.detect.score_threshold, tiles=False)
    base = getattr(detector, "base", detector)
    base.num_threads = threads
    gravity = estimate_gravity(sample_frames(seq, 20, 0, stop))
    graph = BuildPipeline(settings, detector).run(seq, (0, stop), Ground(gravity.up, gravity.floor_height),
                                                  Target("room", "building"))
    nodes = [{"id": o.local_id, "labels": o.labels, "colour": o.colour, "colour2": o.colour2, "shape": o.shape,
              "layer": o.layer, "named_by": o.named_by, "first_frame": o.first_frame, "n_frames": o.n_frames,
              "mean": list(o.mean), "size": list(o.size),
              "box_centre": None if o.box_centre is None else list(o.box_centre)} for o in graph.objects]
    edges = sorted([r.subject, r.predicate, r.object] for r in graph.relations)
    return {"nodes": nodes, "edges": edges, "frames": graph.frames, "up": list(graph.up or ()),
            "raw": _raw_digest(base, seq.frame(0).color)}


if __name__ == "__main__":
    seq_path, stop_at, n_threads, out_path = sys.argv[1:5]
    with open(out_path, "w", encoding="utf-8") as f:
        json.dump(build(seq_path, int(stop_at), int(n_threads)), f)
