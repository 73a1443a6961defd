"""The room suite: every room with ground truth, built fresh with default settings and judged
the same way, in one table.

    python -m benchmarks.bench_rooms [--rooms kitchen,study,living] [--json] [--keep-home DIR]
    python -m benchmarks.bench_rooms --generated N [--first-seed S] [--kinds desk,room,...]

Rooms (read from ../shared beside the checkout):
- kitchen: 7-Scenes red kitchen, ground truth ../shared/eval/kitchen_gt.json;
- study: 3DMatch study room, fragment-1 then fragment-2 built into one room,
  ../shared/eval/studyroom_gt.json;
- living: the synthetic living-room corner, benchmarks/rooms/livingroom_gt.json (written for this
  suite from what the room holds; its method is in the file).

Columns: any-label recall / precision (object-layer nodes of any label, named or not, matched one
to one to every located ground-truth object; the structure layer is not judged), named recall /
precision (nodes a label names against the ground truth's nameable objects: a COCO class, or furniture sg3d names from its shape such as desk or cabinet), duplicates
(any-label), colour agreement of matched named nodes, structure found (floor, walls, surfaces),
furniture named (object nodes whose label is a piece of furniture, with how many were named from
their shape), and the build's seconds per stage. Each room is built into its own scratch store,
so the figures of one room never depend on another's.

`--generated N` judges N seeded layouts of `benchmarks.synth` (dealt round its kinds: a walk
around a room, a desk scan that never sees the floor, a robot camera 0.3 m up, a shelf sweep, a
corner) against their exact ground truth (`benchmarks.synth.judge`), one table line per kind,
instead of the real rooms. Each layout is built with default settings into one scratch store.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
FURNITURE = ("desk", "table", "dining table", "counter", "shelf", "bookcase", "cabinet", "sideboard",
             "couch", "sofa", "bed", "chair", "bench")


@dataclass(frozen=True)
class Room:
    name: str
    sequences: tuple[Path, ...]    # built in this order into the one room
    gt: Path


ROOMS = (
    Room("kitchen", (SHARED / "data" / "7scenes-redkitchen",), SHARED / "eval" / "kitchen_gt.json"),
    Room("study", (SHARED / "data" / "3dmatch-studyroom" / "fragment-1",
                   SHARED / "data" / "3dmatch-studyroom" / "fragment-2"), SHARED / "eval" / "studyroom_gt.json"),
    Room("living", (SHARED / "data" / "open3d-livingroom1-micro",), REPO / "benchmarks" / "rooms" / "livingroom_gt.json"),
)


def _sg3d(home: Path, *args: str) -> dict:
    env = {**os.environ, "SG3D_HOME": str(home)}
    out = subprocess.run([sys.executable, "-m", "sg3d", *args, "--json"], env=env, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"sg3d {' '.join(args)} failed: {out.stderr.strip()[-500:]}")
    return json.loads(out.stdout)


def _objects(home: Path, room: str) -> list[dict]:
    env = {**os.environ, "SG3D_HOME": str(home)}
    out = subprocess.run([sys.executable, "-m", "sg3d", "export", "--room", room, "--out", "-"], env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)["nodes"]


def measure(room: Room, home: Path) -> dict:
    """Build the room fresh into `home`'s store and judge it."""
    seconds: dict[str, float] = {}
    for seq in room.sequences:
        built = _sg3d(home, "build", str(seq), "--room", room.name)
        for stage, s in built["seconds"].items():
            seconds[stage] = round(seconds.get(stage, 0.0) + s, 2)
    report = _sg3d(home, "eval", "--gt", str(room.gt), "--room", room.name, "--no-vqa")
    nodes = _objects(home, room.name)
    furniture = [n for n in nodes if n.get("layer") != "structure" and n["label"] in FURNITURE]
    structure = report["structure"]
    return {
        "room": room.name,
        "any_recall": report["objects"]["recall"], "any_precision": report["objects"]["precision"],
        "named_recall": report["nodes"]["recall"], "named_precision": report["nodes"]["precision"],
        "duplicates": report["objects"]["duplicates"],
        "colour": report["nodes"]["colour"]["agreement"],
        "floor": structure["floor"], "walls": structure["walls"], "surfaces": structure["surfaces"],
        "furniture": sorted(n["label"] for n in furniture),
        "furniture_by_shape": sum(n.get("named_by") == "shape" for n in furniture),
        "nodes": len(nodes),
        "seconds": seconds,
    }


def _fmt(v) -> str:
    return "-" if v is None else f"{v:.2f}"


def table(rows: list[dict]) -> str:
    head = ("room", "any R", "any P", "named R", "named P", "dup", "colour", "structure", "furniture named", "seconds")
    lines = [" | ".join(head), " | ".join("---" for _ in head)]
    for r in rows:
        structure = f"floor {'yes' if r['floor'] else 'no'}, {r['walls']} walls, {len(r['surfaces'])} surfaces"
        furniture = ", ".join(r["furniture"]) or "none"
        furniture += f" ({r['furniture_by_shape']} by shape)"
        stages = ", ".join(f"{k} {v:.1f}" for k, v in r["seconds"].items() if k != "total" and v >= 0.05)
        seconds = f"{r['seconds'].get('total', 0):.1f} ({stages})"
        lines.append(" | ".join((r["room"], _fmt(r["any_recall"]), _fmt(r["any_precision"]), _fmt(r["named_recall"]),
                                 _fmt(r["named_precision"]), str(r["duplicates"]), _fmt(r["colour"]), structure,
                                 furniture, seconds)))
    return "\n".join(lines)


def build_generated(store, kind: str, seed: int, workdir: Path, frames: int = 80) -> dict:
    """Render layout `seed` of `kind` into `workdir`, build it into `store` with default settings
    and judge it (`benchmarks.synth.judge.judge`); the row carries the build's seconds."""
    from benchmarks.synth import generate
    from benchmarks.synth.judge import judge
    from sg3d.app.build import BuildRequest, build_room
    from sg3d.core.model import RELATION_TYPES
    from sg3d.evaluation.evaluate import read_nodes
    from sg3d.graphdb.values import room_id
    from sg3d.ingest.pipeline import Settings

    out = workdir / f"{kind}-{seed}"
    gt = generate(kind, seed, out, frames)
    room = f"{kind}-{seed}"
    summary = build_room(store, BuildRequest(sequence=out, room=room, building="generated"), Settings())
    rid = room_id("generated", room)
    edges = store.read("relation_all", room=rid, types=list(RELATION_TYPES))
    row = judge(gt, read_nodes(store, rid), edges)
    row["seconds"] = round(float(summary.seconds.get("total", 0.0)), 1)
    return row


def measure_generated(n: int, first_seed: int = 0, kinds: Optional[tuple[str, ...]] = None,
                      as_json: bool = False) -> list[dict]:
    from benchmarks.common import scratch_store
    from benchmarks.synth import layouts_for

    rows = []
    with scratch_store() as store, tempfile.TemporaryDirectory(prefix="sg3d-generated-") as tmp:
        for kind, seed in layouts_for(n, first_seed, kinds):
            rows.append(build_generated(store, kind, seed, Path(tmp)))
            print(json.dumps(rows[-1]) if as_json else f"{kind} {seed}: {rows[-1]['floor_said']}, "
                  f"{rows[-1]['matched']}/{rows[-1]['nodes']} nodes matched, missing {rows[-1]['missing']}",
                  file=sys.stdout if as_json else sys.stderr, flush=True)
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--generated", type=int, default=0, metavar="N", help="judge N generated layouts instead")
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--kinds", default=None, help="comma-separated generated kinds (default: all)")
    ap.add_argument("--rooms", default=",".join(r.name for r in ROOMS), help="comma-separated room names")
    ap.add_argument("--json", action="store_true", help="one JSON object per room instead of the table")
    ap.add_argument("--keep-home", type=Path, default=None, help="build into this SG3D_HOME (kept) instead of a scratch one")
    ap.add_argument("--no-figures", action="store_true", help="do not update docs/figures.json (rooms.<room>)")
    args = ap.parse_args(argv)
    if args.generated:
        from benchmarks.synth.judge import table as generated_table

        kinds = tuple(args.kinds.split(",")) if args.kinds else None
        rows = measure_generated(args.generated, args.first_seed, kinds, args.json)
        if not args.json:
            print(generated_table(rows))
        return 0
    wanted = args.rooms.split(",")
    unknown = set(wanted) - {r.name for r in ROOMS}
    if unknown:
        ap.error(f"unknown rooms: {', '.join(sorted(unknown))}")
    rows = []
    for room in (r for r in ROOMS if r.name in wanted):
        missing = [p for p in (*room.sequences, room.gt) if not p.exists()]
        if missing:
            print(f"skipped {room.name}: {missing[0]} is not there", file=sys.stderr)
            continue
        with tempfile.TemporaryDirectory(prefix="sg3d-rooms-") as tmp:
            home = args.keep_home / room.name if args.keep_home else Path(tmp)
            home.mkdir(parents=True, exist_ok=True)
            try:
                rows.append(measure(room, home))
            finally:
                subprocess.run([sys.executable, "-m", "sg3d", "db", "stop"], env={**os.environ, "SG3D_HOME": str(home)},
                               capture_output=True)
        if not args.no_figures:
            from benchmarks.figures import update

            update(f"rooms.{room.name}", {k: v for k, v in rows[-1].items() if k not in ("room", "seconds")})
        if args.json:
            print(json.dumps(rows[-1]), flush=True)
    if not args.json:
        print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
