"""`sg3d ask` latency on a large synthetic store: warm p50/p95 per question type, and cold CLI time.

    python -m benchmarks.bench_ask --objects 100000 --rooms 1000

A scratch embedded store is filled through a bulk UNWIND CREATE (cypher/vqa_bench_load.cypher;
merge_local_graph would take ~100 s for 100k objects) and its per-room tallies recounted, then each question is asked `--repeat`
times through `sg3d.queries.vqa.answer` (store running, taxonomy loaded, embedding never needed), and
once through `python -m sg3d ask` in a fresh process (cold: interpreter, imports, driver).
Each question also says how many queries (Bolt round trips) one answer sends, a figure that
does not move with the machine's load. The last lines sum up what the issue-19 goals name
(store-wide count p50, room-scoped p50 range); `--json` prints every figure as one JSON object,
so runs of two trees can be compared line by line.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks.common import LABELS, CountingStore
from sg3d.core.model import COLOUR_NAMES

QUESTIONS = [
    "how many cups are there?",
    "how many red chairs are in room 17?",
    "how many pieces of furniture are there?",
    "is there a sink in room 3?",
    "how many objects are on the table in room 42?",
    "what is on the table in room 42?",
    "show me the biggest bowl in room 5",
    "how many big bowls are in room 5?",
]


def generate(store, n_objects: int, n_rooms: int, seed: int = 0, batch_rooms: int = 20) -> float:
    from sg3d.graphdb.tally import rebuild_tallies

    rng = np.random.default_rng(seed)
    per_room = max(1, n_objects // n_rooms)
    t0 = time.perf_counter()
    for start in range(0, n_rooms, batch_rooms):
        rooms, pairs = [], []
        for k in range(start, min(n_rooms, start + batch_rooms)):
            rid = f"bench/room {k}"
            objects: list[dict] = []
            for i in range(per_room):
                label = LABELS[i % len(LABELS)]
                size = [float(v) for v in rng.uniform(0.05, 1.5, 3)]
                objects.append({"props": {
                    "id": f"{rid}#{i}", "room": rid, "label": label, "labels": [label], "scores": [0.9],
                    "score": 0.9, "x": float(rng.uniform(0, 10)), "y": float(rng.uniform(0, 3)),
                    "z": float(rng.uniform(0, 10)), "size": size, "volume": float(np.prod(size)),
                    "colour": COLOUR_NAMES[int(rng.integers(len(COLOUR_NAMES)))],
                    "n_points": 100, "observations": 1,
                }, "thumbnail": b"\xff\xd8" + bytes(2000)})
            rooms.append({"id": rid, "name": f"room {k}", "building": "bench", "objects": objects})
            props = [o["props"] for o in objects]
            table = next(o["id"] for o in props if o["label"] == "dining table") if per_room >= 10 else None
            if table:
                pairs += [{"s": o["id"], "o": table, "score": 0.8} for o in props[:per_room // 4]
                          if o["label"] in ("cup", "bowl", "bottle", "vase")]
        store.write("vqa_bench_load", rooms=rooms)
        if pairs:
            store.write("vqa_bench_relations", pairs=pairs)
    rebuild_tallies(store)   # the bulk load bypasses the merge, which keeps them
    return time.perf_counter() - t0


def room_scoped(question: str) -> bool:
    return " in room " in question


def warm(store, repeat: int) -> list[dict]:
    from sg3d.queries.vqa import answer

    out = []
    for q in QUESTIONS:
        counting = CountingStore(store)
        first = answer(counting, q)
        if not first.ok:
            print(f"  refused: {q}: {first.text[:100]}")
            continue
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            answer(store, q)
            times.append((time.perf_counter() - t) * 1000)
        times.sort()
        p95 = times[min(len(times) - 1, int(round(0.95 * (len(times) - 1))))]
        row = {"question": q, "scope": "room" if room_scoped(q) else "store", "p50_ms": round(statistics.median(times), 2),
               "p95_ms": round(p95, 2), "queries": len(counting.sent), "answer": first.text}
        out.append(row)
        print(f"  {row['p50_ms']:7.1f} ms p50 {p95:7.1f} ms p95 {row['queries']:3d} queries  {q!r} -> {first.text[:70]}")
    return out


def summary(rows: list[dict]) -> dict:
    """The figures the issue's goals name: store-wide counts and room-scoped questions, p50."""
    room = [r["p50_ms"] for r in rows if r["scope"] == "room"]
    counts = {r["question"]: r["p50_ms"] for r in rows if r["scope"] == "store"}
    return {"store_wide_p50_ms": counts, "room_scoped_p50_ms": [min(room), max(room)] if room else None,
            "room_scoped_queries": [r["queries"] for r in rows if r["scope"] == "room"]}


def cold(info, question: str) -> float:
    env = dict(os.environ, SG3D_URI=info.uri, SG3D_USER=info.user, SG3D_PASSWORD=info.password,
               SG3D_DATABASE=info.database)
    t = time.perf_counter()
    res = subprocess.run([sys.executable, "-m", "sg3d", "ask", question], env=env,
                         capture_output=True, text=True, timeout=120)
    dt = time.perf_counter() - t
    print(f"  cold CLI {dt:5.2f} s  rc={res.returncode}  {question!r} -> {(res.stdout or res.stderr).strip()[:70]}")
    return dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--objects", type=int, default=100_000)
    ap.add_argument("--rooms", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=30)
    ap.add_argument("--json", action="store_true", help="Also print every figure as one JSON object.")
    args = ap.parse_args()

    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.store import Store

    with tempfile.TemporaryDirectory(prefix="sg3d-bench-ask-") as home:
        server = EmbeddedServer(Path(home))
        info = server.start()
        store = Store(info.uri, (info.user, info.password), info.database)
        try:
            store.ensure_schema()
            dt = generate(store, args.objects, args.rooms)
            n = store.read("object_total")[0]["n"]
            print(f"generated {n} objects in {args.rooms} rooms in {dt:.1f} s ({n / dt:.0f} objects/s)")
            print(f"warm ({args.repeat} runs each, store running, taxonomy loaded):")
            rows = warm(store, args.repeat)
            print("cold (python -m sg3d ask, new process):")
            cold_s = {q: round(cold(info, q), 2) for q in (QUESTIONS[0], QUESTIONS[1])}
            s = summary(rows)
            for q, ms in s["store_wide_p50_ms"].items():
                print(f"store-wide p50 {ms:7.1f} ms  {q!r}")
            if s["room_scoped_p50_ms"]:
                lo, hi = s["room_scoped_p50_ms"]
                print(f"room-scoped p50 {lo:.1f}-{hi:.1f} ms over {len(s['room_scoped_queries'])} questions "
                      f"({min(s['room_scoped_queries'])}-{max(s['room_scoped_queries'])} queries each)")
            if args.json:
                print(json.dumps({"objects": n, "rooms": args.rooms, "repeat": args.repeat, "generate_s": round(dt, 1),
                                  "warm": rows, "cold_s": cold_s, **s}))
        finally:
            store.close()
            server.stop()


if __name__ == "__main__":
    main()
