"""Store benchmark: object upserts/s through the merge path (batched and single) and the merge
latency of a 20-object local graph into a room that already holds 5,000 objects.

    python -m benchmarks.bench_store [--objects 5000] [--batch 500]
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from benchmarks.common import scratch_store, synthetic_object
from graphdb.merge import merge_local_graph
from ingest.embedding import default_embedding
from ingest.model import LocalGraph


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--objects", type=int, default=5000)
    ap.add_argument("--batch", type=int, default=500)
    ap.add_argument("--single", type=int, default=200)
    ap.add_argument("--graphs", type=int, default=30)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    embedding = default_embedding()
    embedding.vectors(["cup"])  # load the model outside the timings

    with scratch_store() as store:
        t0 = time.perf_counter()
        for start in range(0, args.objects, args.batch):
            objs = [synthetic_object(rng, start + i) for i in range(args.batch)]
            merge_local_graph(store, LocalGraph(room="bench", building="b", objects=objs), embedding)
        batched = args.objects / (time.perf_counter() - t0)

        t0 = time.perf_counter()
        for i in range(args.single):
            merge_local_graph(store, LocalGraph(room="single", building="b",
                                                objects=[synthetic_object(rng, i)]), embedding)
        single = args.single / (time.perf_counter() - t0)

        latencies = []
        for g in range(args.graphs):
            objs = [synthetic_object(rng, g * 20 + i, extent=(4.0, 3.0, 4.0)) for i in range(20)]
            t0 = time.perf_counter()
            merge_local_graph(store, LocalGraph(room="bench", building="b", objects=objs), embedding)
            latencies.append((time.perf_counter() - t0) * 1000)

    latencies.sort()
    print(f"{'metric':<52}{'value':>12}")
    print(f"{'upserts/s, batched (' + str(args.batch) + ' objects per transaction)':<52}{batched:>12.0f}")
    print(f"{'upserts/s, single (1 object per transaction)':<52}{single:>12.0f}")
    print(f"{'merge of 20 objects into ' + str(args.objects) + ' in room, p50 ms':<52}{statistics.median(latencies):>12.1f}")
    print(f"{'merge of 20 objects into ' + str(args.objects) + ' in room, p95 ms':<52}{latencies[int(0.95 * (len(latencies) - 1))]:>12.1f}")


if __name__ == "__main__":
    main()
