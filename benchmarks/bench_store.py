"""Store benchmark: object upserts/s through the merge path (batched and single) and the merge
latency of a 20-object local graph into a room that already holds its share of the objects.

    python -m benchmarks.bench_store [--objects 5000] [--rooms 1] [--batch 500]
    python -m benchmarks.bench_store --objects 100000 --rooms 1000     # the reference size

Batched: every room is filled by local graphs of up to --batch objects, one merge transaction
each (with --rooms 1000 and 100,000 objects: 1,000 transactions of 100 objects). Single: one
object per transaction. The 20-object merges land in the first room (objects/rooms objects).
"""
from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np

from benchmarks.common import scratch_store, synthetic_object
from sg3d.core.embedding import default_embedding
from sg3d.core.model import LocalGraph
from sg3d.graphdb.merge import merge_local_graph


def room_name(k: int) -> str:
    return "bench" if k == 0 else f"bench {k}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--objects", type=int, default=5000)
    ap.add_argument("--rooms", type=int, default=1)
    ap.add_argument("--batch", type=int, default=500)
    ap.add_argument("--single", type=int, default=200)
    ap.add_argument("--graphs", type=int, default=30)
    ap.add_argument("--json", action="store_true", help="Also print every figure as one JSON object.")
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    embedding = default_embedding()
    embedding.vectors(["cup"])  # load the model outside the timings
    per_room = max(1, args.objects // args.rooms)
    batch = min(args.batch, per_room)

    with scratch_store() as store:
        t0 = time.perf_counter()
        n = 0
        for k in range(args.rooms):
            for start in range(0, per_room, batch):
                objs = [synthetic_object(rng, n + i) for i in range(min(batch, per_room - start))]
                merge_local_graph(store, LocalGraph(room=room_name(k), building="b", objects=objs), embedding)
                n += len(objs)
        batched = n / (time.perf_counter() - t0)

        t0 = time.perf_counter()
        for i in range(args.single):
            merge_local_graph(store, LocalGraph(room="single", building="b",
                                                objects=[synthetic_object(rng, i)]), embedding)
        single = args.single / (time.perf_counter() - t0)

        latencies = []
        for g in range(args.graphs):
            objs = [synthetic_object(rng, g * 20 + i, extent=(4.0, 3.0, 4.0)) for i in range(20)]
            t0 = time.perf_counter()
            merge_local_graph(store, LocalGraph(room=room_name(0), building="b", objects=objs), embedding)
            latencies.append((time.perf_counter() - t0) * 1000)

    latencies.sort()
    print(f"{'metric':<60}{'value':>12}")
    print(f"{f'upserts/s, batched ({n} objects, {args.rooms} rooms, {batch} per transaction)':<60}{batched:>12.0f}")
    print(f"{'upserts/s, single (1 object per transaction)':<60}{single:>12.0f}")
    print(f"{f'merge of 20 objects into a room of {per_room}, p50 ms':<60}{statistics.median(latencies):>12.1f}")
    p95 = latencies[int(0.95 * (len(latencies) - 1))]
    print(f"{f'merge of 20 objects into a room of {per_room}, p95 ms':<60}{p95:>12.1f}")
    if args.json:
        print(json.dumps({"objects": n, "rooms": args.rooms, "batch": batch, "upserts_per_s_batched": round(batched),
                          "upserts_per_s_single": round(single), "merge20_room_size": per_room,
                          "merge20_p50_ms": round(statistics.median(latencies), 1), "merge20_p95_ms": round(p95, 1)}))


if __name__ == "__main__":
    main()
