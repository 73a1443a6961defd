"""Rooms from one walk: generated apartments (benchmarks.synth, kind apartment) through the places
layer (`sg3d.ingest.places`), judged against their exact room ground truth.

    python -m benchmarks.bench_walk [--n 20] [--first-seed 0] [--json]

Each apartment is rendered, read back as a recording (`sg3d.ingest.readers`), its gravity and
floor estimated from the frames as a build does, its depth lifted into the floor map and the
rooms segmented. Judged per apartment, as Hydra does (Hughes et al., RSS 2022, room metrics over
the free-space places): room precision = the mean over found rooms of the largest share of the
room's free cells that lie in one true room; recall = the mean over true rooms of the largest
share of their seen free cells that one found room holds. Free cells outside every true room
(inside a doorway's wall) are not judged. A true doorway is found when a found passage joins the
found rooms that overlap its two rooms most and lies within DOOR_TOL_M of its middle. An object is in the right room when the found room at its
true position (`places.room_at`) overlaps its true room most: this judges the rooms, not the
object detector.
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

# A half-open leaf narrows a door's passage to the gap between its edge and the far jamb, up to
# a leaf's length (0.6 m at 45 degrees) inside the room; the passage must join the right rooms.
DOOR_TOL_M = 1.0


def places_of(folder: Path):
    """The places layer of a recording folder: (Places, basis, floor height)."""
    from sg3d.core.geometry import horizontal_frame
    from sg3d.ingest.places import rooms_of_walk, walk_points
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames
    from sg3d.ingest.readers import open_sequence

    seq = open_sequence(folder)
    g = estimate_gravity(sample_frames(seq, 20, 0, len(seq)))
    basis = horizontal_frame(g.up)
    floor = float(g.floor_height if g.floor_height is not None else 0.0)
    frames = [seq.frame(i) for i in range(len(seq))]
    points, cameras = walk_points(frames, basis, floor)
    return rooms_of_walk(points, cameras), basis, floor


def to_room_frame(ab: np.ndarray, basis: np.ndarray, floor: float, T: np.ndarray) -> np.ndarray:
    """Gravity-frame (a, b) on the floor -> the generator's room frame (x, y)."""
    local = np.c_[ab, np.full(len(ab), floor)]
    world = local @ basis
    return ((world - T[:3, 3]) @ T[:3, :3])[:, :2]


def to_gravity(xy: np.ndarray, basis: np.ndarray, T: np.ndarray) -> np.ndarray:
    world = np.c_[xy, np.zeros(len(xy))] @ T[:3, :3].T + T[:3, 3]
    return (world @ basis.T)[:, :2]


def judge(gt: dict, places, basis: np.ndarray, floor: float) -> dict:
    """Room precision and recall (Hydra), doorways found, objects in the right room."""
    from matplotlib.path import Path as Polygon

    from sg3d.ingest.places import room_at
    from sg3d.ingest.places.floor_map import FREE

    T = np.asarray(gt["room_to_world"], float)
    apt = gt["apartment"]
    fm = places.floor
    free = np.argwhere(fm.state == FREE)
    xy = to_room_frame(fm.centres(free), basis, floor, T)
    truth = np.zeros(len(free), np.int64)
    for k, r in enumerate(apt["rooms"], start=1):
        truth[Polygon(r["polygon"]).contains_points(xy)] = k
    found = places.labels[free[:, 0], free[:, 1]]
    judged = truth > 0
    overlap = np.zeros((len(places.rooms) + 1, len(apt["rooms"]) + 1), np.int64)
    np.add.at(overlap, (found[judged], truth[judged]), 1)
    o = overlap[1:, 1:]
    prec = [row.max() / row.sum() for row in o if row.sum()]
    rec_rows = [(o[:, j].max() if len(o) else 0) / overlap[:, j + 1].sum() for j in range(o.shape[1])
                if overlap[:, j + 1].sum()]
    best = {k + 1: int(np.argmax(row)) + 1 for k, row in enumerate(o) if row.sum()}
    passages = to_room_frame(np.array([d.position for d in places.doorways]).reshape(-1, 2), basis, floor, T)
    ids = {r["id"]: k for k, r in enumerate(apt["rooms"], start=1)}
    joins = [{best.get(d.a), best.get(d.b)} for d in places.doorways]
    door_found = [any(j == {ids[r] for r in d["rooms"]} and float(np.linalg.norm(p - d["position"])) <= DOOR_TOL_M
                      for j, p in zip(joins, passages)) for d in apt["doorways"]]
    objs = [ob for ob in gt["objects"] if ob["seen"]]
    centres = np.array([[(a + b) / 2 for a, b in zip(ob["box_gravity"]["min"][:2], ob["box_gravity"]["max"][:2])]
                        for ob in objs]).reshape(-1, 2)
    at = room_at(places, to_gravity(centres, basis, T)) if len(objs) else np.zeros(0, int)
    right = [best.get(int(k)) == ids[ob["room"]] for k, ob in zip(at, objs)]
    return {"seed": gt["seed"], "rooms_true": len(apt["rooms"]), "rooms_found": len(places.rooms),
            "precision": round(float(np.mean(prec)) if prec else 0.0, 3),
            "recall": round(float(np.mean(rec_rows)) if rec_rows else 0.0, 3),
            "doorways": len(apt["doorways"]), "doorways_found": int(sum(door_found)),
            "doorways_missed": [f"{d['id']} {d['kind']} {d['width']:.2f} m seen {d['frames_seen']}x"
                                for d, ok in zip(apt["doorways"], door_found) if not ok],
            "passages": len(places.doorways),
            "objects": len(objs), "objects_right": int(sum(right)),
            "objects_wrong": [f"{ob['id']} {ob['category']} in {ob['room']}" for ob, ok in zip(objs, right) if not ok]}


def measure(seed: int, workdir: Path) -> dict:
    from benchmarks.synth import generate

    t0 = time.perf_counter()
    gt = generate("apartment", seed, workdir / f"apartment-{seed}")
    t1 = time.perf_counter()
    places, basis, floor = places_of(workdir / f"apartment-{seed}")
    row = judge(gt, places, basis, floor)
    row["frames"] = gt["frames"]
    row["seconds"] = {"render": round(t1 - t0, 1), "places": round(time.perf_counter() - t1, 1)}
    return row


def table(rows: list[dict], worst: int = 5) -> str:
    n = len(rows)
    P = np.mean([r["precision"] for r in rows])
    R = np.mean([r["recall"] for r in rows])
    doors = sum(r["doorways_found"] for r in rows) / max(1, sum(r["doorways"] for r in rows))
    objs = sum(r["objects_right"] for r in rows) / max(1, sum(r["objects"] for r in rows))
    lines = [f"{n} apartments: room precision {P:.3f}, recall {R:.3f}, doorways found {doors:.1%}, "
             f"objects in the right room {objs:.1%}", "",
             "seed | rooms true/found | P | R | doorways | objects | missed doorways, wrong objects",
             "--- | --- | --- | --- | --- | --- | ---"]
    for r in sorted(rows, key=lambda r: min(r["precision"], r["recall"]))[:worst]:
        why = "; ".join(r["doorways_missed"] + r["objects_wrong"][:3]) or "-"
        lines.append(f"{r['seed']} | {r['rooms_true']}/{r['rooms_found']} | {r['precision']:.2f} | {r['recall']:.2f} | "
                     f"{r['doorways_found']}/{r['doorways']} | {r['objects_right']}/{r['objects']} | {why}")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20, help="apartments (seeds first-seed .. first-seed + n - 1)")
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--worst", type=int, default=6, help="table lines: the worst layouts")
    ap.add_argument("--json", action="store_true", help="one JSON object per apartment instead of the table")
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory(prefix="sg3d-walk-") as tmp:
        for seed in range(args.first_seed, args.first_seed + args.n):
            rows.append(measure(seed, Path(tmp)))
            r = rows[-1]
            print(json.dumps(r) if args.json else f"seed {seed}: rooms {r['rooms_true']}/{r['rooms_found']} "
                  f"P {r['precision']:.2f} R {r['recall']:.2f} doorways {r['doorways_found']}/{r['doorways']} "
                  f"objects {r['objects_right']}/{r['objects']} {r['seconds']}",
                  file=sys.stdout if args.json else sys.stderr, flush=True)
    if not args.json:
        print(table(rows, args.worst))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
