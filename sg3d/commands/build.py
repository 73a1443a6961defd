"""`sg3d build`: a posed RGB-D sequence -> the room's 3-D scene graph in the store."""
from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Optional

import click

from sg3d.errors import UserError


def _summary_table(summary: dict):
    from rich.table import Table

    t = Table(title=f"sg3d build: {summary['building']}/{summary['room']} ({summary['method']})",
              show_header=False)
    f = summary["frames"]
    t.add_row("frames", f"{f['read']} read, {f['skipped']} skipped, {f['blurry']} blurry")
    t.add_row("keyframe groups", f"{f['groups']} ({f['keyframes']} keyframes + {f['anchors']} anchors "
                                 f"= {f['kept']} frames detected, {100 * f['fraction_kept']:.1f} %)")
    g = summary["graph"]
    t.add_row("merged", f"{g['merged_groups']} groups ({g['skipped_groups']} already merged)")
    t.add_row("objects", f"{g['objects_created']} new, {g['objects_updated']} updated; room now holds {g['room_objects']}")
    t.add_row("relations", f"{g['relations']} merged; room now holds {g['room_relations']}")
    stages = ", ".join(f"{k} {v:.2f}" for k, v in summary["seconds"].items())
    t.add_row("seconds", stages)
    t.add_row("speed", f"{summary['input_frames_per_second']:.1f} input frames/s")
    if summary.get("placement"):
        t.add_row("in building", ", ".join(f"{k} {v}" for k, v in summary["placement"].items()))
    return t


@click.command()
@click.argument("sequence", type=click.Path(path_type=Path))
@click.option("--room", required=True, help="Room name; the graph of this room is created or extended.")
@click.option("--building", default="default", show_default=True, help="Building the room belongs to.")
@click.option("--method", type=click.Choice(["2d-basic", "2d-efficient", "3d-basic", "3d-efficient", "3d-full"]),
              default="3d-full", show_default=True, help="Modules to run (the paper's Table I presets).")
@click.option("--layout", type=click.Choice(["7scenes", "3dmatch", "tum", "scannet"]), default=None,
              help="Sequence layout (default: detected).")
@click.option("--start", type=int, default=0, show_default=True, help="First frame index.")
@click.option("--stop", type=int, default=None, help="Stop before this frame index.")
@click.option("--resume", is_flag=True, help="Continue after the last keyframe group merged by this build.")
@click.option("--detector", default=None, metavar="NAME|MODEL.onnx",
              help="Detector: ssd-mobilenet-v2-coco (default) or your own ONNX model (labels file beside it).")
@click.option("--score-threshold", type=float, default=0.23, show_default=True, help="Detection score threshold.")
@click.option("--abir-gain", type=float, default=None, help="ABIR gain g of Eq. 4 (default 10, the authors' code).")
@click.option("--t-key", type=float, default=0.2, show_default=True, help="KGE keyframe overlap threshold.")
@click.option("--t-anchor", type=float, default=0.9, show_default=True,
              help="KGE anchor overlap threshold (authors' code: 0.68, which keeps 2 % of the kitchen and misses its sink).")
@click.option("--transform", "transform_file", type=click.Path(exists=True, dir_okay=False, path_type=Path),
              default=None, help="4x4 room-to-building transform (4 lines of 4 numbers).")
@click.option("--align-to", default=None, metavar="ROOM",
              help="Place the room in the building by aligning its objects to ROOM's (RANSAC + Kabsch).")
@click.option("--shared-frame", is_flag=True,
              help="The sequence shares the building's world frame (identity transform).")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON (no progress bar).")
@click.pass_obj
def build(settings, sequence: Path, room: str, building: str, method: str, layout: Optional[str],
          start: int, stop: Optional[int], resume: bool, detector: Optional[str], score_threshold: float,
          abir_gain: Optional[float], t_key: float, t_anchor: float, transform_file: Optional[Path],
          align_to: Optional[str], shared_frame: bool, as_json: bool) -> None:
    """Build (or extend) the 3-D scene graph of ROOM from the RGB-D SEQUENCE folder.

    Runs blur rejection (ABIR), keyframe groups (KGE), detection, 3-D attributes, spurious
    detection rejection (SDR) and relations, and merges each keyframe group's local graph into
    the store as one transaction. Re-running the same build merges nothing twice; after Ctrl-C
    or a crash, --resume continues after the last merged group.

    Rooms of one building: the first room placed in a building is its reference frame; place
    the others with --shared-frame, --transform FILE or --align-to ROOM (see `sg3d rooms`).
    """
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from graphdb.merge import merge_local_graph, merged_keys, room_id
    from graphdb.similarity import SimilarityParams
    from ingest.detect import SsdMobilenetDetector, make_detector
    from ingest.embedding import default_embedding
    from ingest.gravity import estimate_gravity, sample_frames
    from ingest.model import RELATION_TYPES
    from ingest.pipeline import (METHODS, PipelineStats, local_graph, make_selector, run_key,
                                 single_frame_groups)
    from ingest.readers import open_sequence

    if not room.strip() or not building.strip() or "/" in room or "/" in building:
        raise UserError("room and building names must be non-empty and contain no '/'")
    if start < 0 or (stop is not None and stop <= start):
        raise UserError(f"--start {start} --stop {stop}: the frame range is empty (need 0 <= start < stop)")
    if sum(map(bool, (transform_file, align_to, shared_frame))) > 1:
        raise UserError("give at most one of --transform, --align-to and --shared-frame")
    placement = None
    if transform_file is not None:
        from graphdb.building import TransformError, load_transform

        try:
            placement = load_transform(transform_file)  # read before the long build, fail early
        except TransformError as exc:
            raise UserError(str(exc))
    t_start = time.perf_counter()
    seq = open_sequence(sequence, layout)
    if len(seq) == 0:
        raise UserError(f"no frames found in {sequence}")
    m = METHODS[method]
    store = settings.store()
    store.ensure_schema()
    rid = room_id(building, room)
    run = run_key(str(sequence.resolve()), len(seq), m, room, building)
    done = merged_keys(store, run + ":")
    if resume and done:
        last = max(int(k.rsplit(":", 1)[1].split("-")[1]) for k in done)
        start = max(start, last + 1)

    t0 = time.perf_counter()
    try:
        gravity = estimate_gravity(sample_frames(seq, 20))
        up = gravity.up
    except ValueError:
        raise UserError(f"no frame of {sequence} has usable depth")
    t_gravity = time.perf_counter() - t0

    if detector is None:
        det = SsdMobilenetDetector(score_threshold=score_threshold)
    else:
        try:
            det = make_detector(detector)
        except (ValueError, FileNotFoundError) as exc:
            raise UserError(str(exc))
    embedding = default_embedding()
    params = SimilarityParams() if m.three_d else SimilarityParams(threshold=float("inf"))

    selector = make_selector(abir_gain, t_key, t_anchor)
    if m.efficient:
        groups = selector.groups(seq, start, stop)
    else:
        groups = single_frame_groups(seq, start, stop, selector.stats)
    stats = PipelineStats()
    totals = {"merged_groups": 0, "skipped_groups": 0, "objects_created": 0, "objects_updated": 0, "relations": 0}
    merge_seconds = 0.0
    consumer_seconds = 0.0
    n_total = len(range(start, len(seq) if stop is None else min(stop, len(seq))))
    console = Console(stderr=True)
    progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                        TextColumn("{task.fields[info]}"), TimeElapsedColumn(),
                        console=console, disable=as_json, transient=False)
    interrupted = False
    with progress:
        task = progress.add_task("frames", total=n_total, info="")
        try:
            for group in groups:
                c0 = time.perf_counter()
                # keyed by its keyframe: the same group of an earlier run of this build is skipped
                key = f"{run}:{group.frames[0].index}-{group.frames[-1].index}"
                if any(k.startswith(f"{run}:{group.frames[0].index}-") for k in done):
                    totals["skipped_groups"] += 1
                else:
                    lg = local_graph(group, det, up, m, room, building, key, stats)
                    t0 = time.perf_counter()
                    report = merge_local_graph(store, lg, embedding, params)
                    merge_seconds += time.perf_counter() - t0
                    totals["merged_groups"] += 0 if report.skipped else 1
                    totals["objects_created"] += report.created
                    totals["objects_updated"] += report.updated
                    totals["relations"] += report.relations
                for frame in group.frames:
                    frame.release()
                consumer_seconds += time.perf_counter() - c0
                st = selector.stats
                progress.update(task, completed=min(n_total, st.read + st.skipped),
                                info=f"groups {st.groups}  keyframes {st.kept}  objects +{totals['objects_created']}"
                                     f"  relations {totals['relations']}")
        except KeyboardInterrupt:
            interrupted = True
        progress.update(task, completed=min(n_total, selector.stats.read + selector.stats.skipped))

    placed = None if interrupted else _place_room(store, building, room, placement, align_to, shared_frame)
    st = selector.stats
    wall = time.perf_counter() - t_start
    room_objects = store.read("object_count", room=rid)[0]["n"]
    room_relations = store.read("relation_count", room=rid, types=list(RELATION_TYPES))[0]["n"]
    seconds = {
        "gravity": t_gravity,
        "read+abir+kge": max(0.0, st.seconds - consumer_seconds),
        **{k: v for k, v in stats.seconds.items()},
        "merge": merge_seconds,
        "total": wall,
    }
    summary = {
        "sequence": str(sequence), "room": room, "building": building, "method": method,
        "interrupted": interrupted, "up": [round(float(v), 4) for v in up],
        "frames": {**{k: v for k, v in st.as_dict().items() if k not in ("seconds", "frames_per_second")},
                   "detected": stats.frames_detected, "detections": stats.detections},
        "graph": {**totals, "room_objects": room_objects, "room_relations": room_relations},
        "seconds": {k: round(v, 3) for k, v in seconds.items()},
        "input_frames_per_second": round(st.frames / wall, 2) if wall > 0 else 0.0,
        "frames_read": st.read, "key": run, "placement": placed,
    }
    if as_json:
        click.echo(json.dumps(summary))
    else:
        Console().print(_summary_table(summary))
    if interrupted:
        click.echo(f"interrupted: {totals['merged_groups']} groups merged and kept; "
                   f"run the same command with --resume to continue", err=True)
        raise SystemExit(130)


def _place_room(store, building: str, room: str, transform, align_to: Optional[str], shared_frame: bool):
    """Give the room its room-to-building transform; a building's first room is its reference."""
    import numpy as np

    from graphdb.align import AlignmentError
    from graphdb.building import link_rooms, list_rooms, room_id_of, set_room_transform

    rid = room_id_of(building, room)
    try:
        if align_to:
            report = link_rooms(store, room_id_of(building, align_to), rid)
            return {"how": f"aligned to {align_to}", "residual_m": round(report.residual_rms_m, 4),
                    "pairs": report.pairs, "same_as": len(report.same_as)}
        if transform is not None:
            set_room_transform(store, rid, transform)
            return {"how": "transform file"}
        placed = [r for r in list_rooms(store, building) if r["id"] != rid and r["to_building"] is not None]
        if shared_frame or not placed:
            set_room_transform(store, rid, np.eye(4))
            return {"how": "shared frame" if shared_frame else "reference room of the building"}
    except AlignmentError as exc:
        raise UserError(f"the graph was built, but placing it in the building failed: {exc}")
    return {"how": "not placed yet: `sg3d rooms link`, or build with --align-to/--transform/--shared-frame"}


commands = [build]
