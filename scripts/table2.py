"""The paper's Table II on a real sequence: build the scene graph once per Table I method preset,
evaluate each against ground truth, print one table.

    python scripts/table2.py [SEQUENCE] [--gt FILE] [--method M ...] [--tag T] [--stop N] [--json]

Each method builds room `table2-<method>[-<tag>]`. A build merges nothing twice, so re-running
into an existing room times nothing: pass a new --tag (or wipe the store) for fresh timings.
Defaults resolve against the repository root: ../shared/data/7scenes-redkitchen and
../shared/eval/kitchen_gt.json.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
METHODS = ("2d-basic", "2d-efficient", "3d-basic", "3d-efficient", "3d-full", "3d-full-high")
# a row name -> (the --method preset, extra build flags)
PRESETS = {m: (m, []) for m in METHODS[:-1]} | {"3d-full-high": ("3d-full", ["--quality", "high"])}
DEFAULT_SEQUENCE = REPO.parent / "shared" / "data" / "7scenes-redkitchen"
DEFAULT_GT = REPO.parent / "shared" / "eval" / "kitchen_gt.json"


def sg3d(global_args: list[str], *args: str) -> dict:
    """Run one `sg3d ... --json` command and return its JSON; exit with its error otherwise."""
    cmd = [sys.executable, "-m", "sg3d", *global_args, *args, "--json"]
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd[2:])} failed ({proc.returncode}): {proc.stderr.strip() or proc.stdout.strip()}")
    return json.loads(proc.stdout)


def row_of(method: str, build: dict, report: dict, wall: float) -> dict:
    n, e = report["nodes"], report["edges"]
    frames = build.get("frames", {}).get("read") or 0
    seconds = build.get("seconds", {})
    total = seconds.get("total", wall) if isinstance(seconds, dict) else float(seconds)
    return {
        "method": method,
        "nodes": n["graph_nodes"],
        "spurious_nodes": len(n["spurious"]),
        "duplicate_nodes": len(n["duplicates"]),
        "missing_nodes": len(n["missing"]),
        "node_precision": n["precision"],
        "node_recall": n["recall"],
        "edges": e["graph_edges"],
        "spurious_edges": len(e["spurious"]),
        "missing_edges": len(e["missed"]) + len(e["unmapped"]["end_not_matched"]),
        "edge_precision": e["precision"],
        "edge_recall": e["recall"],
        # every object, named or not, against all located GT objects
        "object_nodes": report.get("objects", {}).get("nodes"),
        "object_precision": report.get("objects", {}).get("precision"),
        "object_recall": report.get("objects", {}).get("recall"),
        "frames_read": frames,
        "seconds_per_frame": (total / frames) if frames else None,
    }


# short headers so the table fits a terminal
HEADERS = {"spurious_nodes": "spur N", "duplicate_nodes": "dup N", "missing_nodes": "miss N",
           "node_precision": "P node", "node_recall": "R node", "spurious_edges": "spur E",
           "missing_edges": "miss E", "edge_precision": "P edge", "edge_recall": "R edge",
           "object_nodes": "all N", "object_precision": "P all", "object_recall": "R all",
           "frames_read": "frames", "seconds_per_frame": "s/frame"}


def print_table(rows: list[dict]) -> None:
    from rich.console import Console
    from rich.table import Table

    def fmt(v) -> str:
        if v is None:
            return "-"
        return f"{v:.3f}" if isinstance(v, float) else str(v)

    table = Table(title="Table II: scene graph quality and speed per method")
    for key in rows[0]:
        table.add_column(HEADERS.get(key, key), justify="left" if key == "method" else "right")
    for r in rows:
        table.add_row(*(fmt(v) for v in r.values()))
    Console().print(table)
    Console().print("missing edges = GT relations not found, an unmatched end included; "
                    "spurious edges are judged between matched nodes only", style="dim")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sequence", nargs="?", type=Path, default=DEFAULT_SEQUENCE)
    ap.add_argument("--gt", type=Path, default=DEFAULT_GT)
    ap.add_argument("--method", action="append", choices=METHODS, help="Repeatable; default: all five and the high-quality 3d-full.")
    ap.add_argument("--building", default="default")
    ap.add_argument("--tag", default="", help="Suffix for the room names (fresh rooms, fresh timings).")
    ap.add_argument("--stop", type=int, default=None, help="Stop before this frame index (quick runs).")
    ap.add_argument("--tolerance", type=float, default=None, help="Matching tolerance in metres.")
    ap.add_argument("--home", default=None, help="Embedded store home (passed to sg3d --home).")
    ap.add_argument("--json", action="store_true", help="Rows as JSON instead of a table.")
    args = ap.parse_args(argv)
    if not args.gt.exists():
        sys.exit(f"ground truth not found: {args.gt}")
    global_args = ["--home", args.home] if args.home else []
    rows = []
    for method in args.method or METHODS:
        room = f"table2-{method}" + (f"-{args.tag}" if args.tag else "")
        preset, extra = PRESETS[method]
        build_args = ["build", str(args.sequence), "--room", room, "--building", args.building, "--method", preset, *extra]
        if args.stop is not None:
            build_args += ["--stop", str(args.stop)]
        t0 = time.perf_counter()
        build = sg3d(global_args, *build_args)
        wall = time.perf_counter() - t0
        eval_args = ["eval", "--gt", str(args.gt), "--room", room, "--building", args.building, "--no-vqa"]
        if args.tolerance is not None:
            eval_args += ["--tolerance", str(args.tolerance)]
        report = sg3d(global_args, *eval_args)
        rows.append(row_of(method, build, report, wall))
        print(f"{method}: done in {wall:.0f} s", file=sys.stderr)
    if args.json:
        print(json.dumps(rows))
    else:
        print_table(rows)


if __name__ == "__main__":
    main()
