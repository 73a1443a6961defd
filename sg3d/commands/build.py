"""`sg3d build`: a posed RGB-D sequence -> the room's 3-D scene graph in the store."""
from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import click

from sg3d.commands.bag_options import bag_options
from sg3d.commands.config_options import config_options, flag_of
from sg3d.commands.names import checked_name
from sg3d.errors import UserError
from sg3d.ingest.config import DEFAULT_METHOD, METHODS, BuildConfig, DetectConfig, SelectConfig, default_of, help_of

if TYPE_CHECKING:
    from sg3d.settings import Settings


def _summary_table(summary: dict):
    from rich.table import Table

    interrupted = summary.get("interrupted")
    t = Table(title=f"sg3d build: {summary['building']}/{summary['room']} ({summary['method']}, "
                    f"{summary['quality']} quality){', interrupted' if interrupted else ''}", show_header=False)
    f = summary["frames"]
    t.add_row("frames", f"{f['read']} read of {f['in_range']}, {f['skipped']} skipped, {f['blurry']} blurry")
    chosen = f["keyframes"] + f["anchors"] + f["coverage"]
    detected = (f"{f['detected']} of {chosen} chosen frames" if interrupted and f["detected"] < chosen
                else f"{f['detected']} frames")
    # detections are counted when a chunk's detection pass ends: after Ctrl-C the frames detected
    # in the chunk that was cut short are in `detected` but their detections are not
    detections = (f"{f['detections']} detections in the finished chunks" if interrupted
                  else f"{f['detections']} detections")
    t.add_row("detected", f"{detected} ({f['keyframes']} keyframes + {f['anchors']} anchors + "
                          f"{f['coverage']} for new viewpoints), {detections}")
    h = summary["hypotheses"]
    rejected = ", ".join(f"{n} {why}" for why, n in h["rejected"].items()) or "none"
    t.add_row("objects found", f"{h['formed']} candidates, {h['kept']} kept (rejected: {rejected})")
    d = summary.get("from_depth") or {}
    if d.get("unnamed") or d.get("structure"):
        # only a walk's build looks for windows (`--rooms auto`)
        kinds = "floor, walls, windows, surfaces" if summary.get("rooms_found") is not None else "floor, walls, surfaces"
        t.add_row("from depth", f"{d.get('unnamed', 0)} objects no detector named, {d.get('structure', 0)} of the "
                                f"room's structure ({kinds})")
    if summary.get("floor") == "not seen":
        t.add_row("floor", "not seen (no floor in view: the tops seen are objects, with what lies on them)")
    g = summary["graph"]
    t.add_row("merged", f"{g['merged_chunks']} of {g['chunks']} chunks ({g['skipped_chunks']} already merged)")
    folded = f", {g['objects_folded']} folded into the object they were part of" if g.get("objects_folded") else ""
    t.add_row("objects", f"{g['objects_created']} new, {g['objects_updated']} updated, {g.get('objects_moved', 0)} moved, "
                         f"{g.get('objects_removed', 0)} removed{folded}; room now holds {g['room_objects']}")
    if summary.get("scan"):
        t.add_row("scan", f"{summary['scan']} (`sg3d changes --room {summary['room']}` shows what it changed)")
    t.add_row("relations", f"{g['relations']} merged; room now holds {g['room_relations']}")
    if summary.get("rooms_found") is not None:
        t.add_row("rooms found", _rooms_text(summary["rooms_found"]))
    t.add_row("seconds", ", ".join(f"{k} {v:.2f}" for k, v in summary["seconds"].items()))
    if not interrupted and f["read"]:    # a speed over a run cut short, or over no frame, means nothing
        t.add_row("speed", f"{summary['input_frames_per_second']:.1f} input frames/s")
    if summary.get("placement"):
        t.add_row("in building", _placement_text(summary["placement"]))
    poses = summary.get("poses") or {}
    if poses.get("source") == "estimated":
        t.add_row("poses", _poses_text(poses))
    if f["skipped_frames"]:
        shown = "; ".join(f"{s['frame']}: {s['reason']}" for s in f["skipped_frames"][:5])
        more = len(f["skipped_frames"]) - 5
        t.add_row("skipped frames", shown + (f"; and {more} more (--json lists all)" if more > 0 else ""))
    return t


def _sequence(sequence: Optional[Path], sample_name: Optional[str]) -> Path:
    """The folder to build: SEQUENCE, or the verified copy of sample NAME (one error line when it
    cannot be had, so `sg3d build --sample kitchen` stops there)."""
    if (sequence is None) == (sample_name is None):
        raise click.UsageError("give a SEQUENCE folder or bag, or --sample NAME (one of them)")
    if sequence is not None:
        return sequence
    from sg3d.app.errors import AppError
    from sg3d.commands.sample import locate_with_progress

    try:
        return locate_with_progress(str(sample_name)).path
    except AppError as exc:
        raise UserError(str(exc)) from None


def _poses_text(poses: dict) -> str:
    """The estimated trajectory in words: length, loop closures, frames that could not be placed."""
    text = (f"estimated: {poses['trajectory_m']:.2f} m travelled, {poses['loop_closures']} loop closures, "
            f"{poses['placed']} frames placed, {poses['unplaced']} not placed")
    if poses["segments"] > 1:
        lost, linked = poses["segments"] - 1, poses["segments_linked"]
        text += (f"; tracking lost {'once' if lost == 1 else f'{lost} times'}, {linked} "
                 f"segment{'' if linked == 1 else 's'} found again")
    if poses["unplaced_frames"]:
        shown = "; ".join(f"{u['frame']}: {u['reason']}" for u in poses["unplaced_frames"][:3])
        more = len(poses["unplaced_frames"]) - 3
        text += f" ({shown}{f'; and {more} more, --json lists all' if more > 0 else ''})"
    if poses.get("trajectory_file"):
        text += f"; trajectory in {poses['trajectory_file']}"
    return text


def _room_name(room: Optional[str], rooms: Optional[str], sequence: Path) -> str:
    """--room, or with --rooms auto and no --room the recording's folder name."""
    if room is None and rooms is None:
        raise click.UsageError("give --room NAME, or --rooms auto to find the rooms of the walk")
    return room or Path(sequence).resolve().name


def _rooms_text(found: dict) -> str:
    """sg3d.app.places.write_walk_rooms's dict in words: the rooms, their objects and kind guesses."""
    if not found["rooms"]:
        return f"none ({found.get('why', 'no free floor was seen')})"
    rooms = "; ".join(f"{r['name']} {r['area']:.1f} m2, {r['objects']} objects"
                      + (f", looks like a {r['kind_guess']}" if r["kind_guess"] else "") for r in found["rooms"])
    return f"{len(found['rooms'])} ({rooms}); {found['doorways']} doorways"


def _placement_text(placement: dict) -> str:
    """sg3d.app.build.place_room's dict in words: how the room was placed, then the alignment's figures."""
    extra = []
    if "residual_m" in placement:
        extra.append(f"residual {placement['residual_m']} m")
    if "pairs" in placement:
        extra.append(f"{placement['pairs']} object pairs")
    if "same_as" in placement:
        extra.append(f"{placement['same_as']} objects linked SAME_AS")
    return placement["how"] + (f" ({', '.join(extra)})" if extra else "")


@click.command()
@click.argument("sequence", type=click.Path(path_type=Path), required=False)
@click.option("--sample", "sample_name", default=None, metavar="NAME",
              help="Build sample recording NAME instead of a SEQUENCE (found or downloaded as `sg3d sample NAME` does).")
@click.option("--room", default=None, callback=checked_name,
              help="Room name (printable, any script; no '/', '\\' or '..'); the graph of this room is "
                   "created or extended. Required unless --rooms auto (then: the recording's folder name).")
@click.option("--rooms", "rooms", type=click.Choice(["auto"]), default=None,
              help="auto: also find the rooms the walk went through (floor map, rooms, doorways) and put "
                   "each object in one of them.")
@click.option("--building", default="default", show_default=True, callback=checked_name,
              help="Building the room belongs to (same rule as --room).")
@click.option("--method", type=click.Choice(list(METHODS)), default=DEFAULT_METHOD, show_default=True, help="Modules to run (the paper's Table I presets).")
@click.option("--quality", type=click.Choice(["default", "high"]), default=default_of(DetectConfig, "quality"),
              help=help_of(DetectConfig, "quality"))
@click.option("--layout", type=click.Choice(["7scenes", "3dmatch", "tum", "scannet", "open3d", "plain"]), default=None,
              help="Sequence layout (default: detected).")
@click.option("--start", type=int, default=0, show_default=True, help="First frame index.")
@click.option("--stop", type=int, default=None, help="Stop before this frame index.")
@click.option("--resume", is_flag=True,
              help="Continue an interrupted build. (Chunks already merged by the same build are always "
                   "skipped, so this only states the intent.)")
@click.option("--detector", default=None, metavar="NAME|MODEL.onnx",
              help=help_of(DetectConfig, "detector"))
@click.option("--recognizer", type=click.Choice(["none", "efficientnet"]), default="none", show_default=True,
              help="efficientnet: re-rank each box's labels with the shipped EfficientNet-Lite3 ImageNet "
                   "classifier (the paper's recognition module; needs the recognize extra, ~10 ms per box).")
@click.option("--score-threshold", type=click.FloatRange(0.0, 1.0), default=default_of(DetectConfig, "score_threshold"),
              help=help_of(DetectConfig, "score_threshold"))
@click.option("--chunk-frames", type=click.IntRange(min=10), default=None,
              help=help_of(BuildConfig, "chunk_frames"))
@config_options(SelectConfig, ("detect_fraction", "abir_gain", "t_key", "t_anchor"), "select",
                extra_help={"abir_gain": "Not with --method 2d-basic/3d-basic."})
@click.option("--transform", "transform_file", type=click.Path(exists=True, dir_okay=False, path_type=Path),
              default=None, help="4x4 room-to-building transform (4 lines of 4 numbers).")
@click.option("--align-to", default=None, metavar="ROOM",
              help="Place the room in the building by aligning its objects to ROOM's (RANSAC + Kabsch).")
@click.option("--shared-frame", is_flag=True,
              help="The sequence shares the building's world frame (identity transform).")
@click.option("--estimate-poses", is_flag=True,
              help="Estimate the camera poses from the images (RGB-D odometry, loop closures, pose graph) "
                   "even when the recording has its own; recordings without poses get this anyway.")
@click.option("--trajectory-out", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Write the estimated camera trajectory to this file (TUM format: t tx ty tz qx qy qz qw).")
@click.option("--wait", is_flag=True,
              help="When another build, map or ingest is writing ROOM, wait for it instead of refusing.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON (no progress bar).")
@bag_options
@click.pass_obj
def build(settings: Settings, sequence: Path, room: str, building: str, method: str, quality: str, layout: Optional[str],
          start: int, stop: Optional[int], resume: bool, detector: Optional[str], recognizer: str,
          score_threshold: float,
          select: dict[str, Any], chunk_frames: Optional[int], transform_file: Optional[Path], align_to: Optional[str],
          shared_frame: bool, estimate_poses: bool, trajectory_out: Optional[Path], wait: bool, as_json: bool,
          bag: dict, sample_name: Optional[str], rooms: Optional[str] = None) -> None:
    """Build (or extend) the 3-D scene graph of ROOM from the RGB-D SEQUENCE folder or ROS bag
    (ROS1 .bag, ROS2 bag folder, .mcap; topics are picked when unambiguous, see the --*-topic options).

    Runs blur rejection (ABIR), keyframe groups (KGE) plus frames with new viewpoints, detection,
    3-D attributes, fusion over the whole sequence, multi-view existence tests and relation votes
    (SDR), and merges the result into the store, one transaction per chunk. Re-running the same
    build merges nothing twice; after Ctrl-C or a crash, the same command (or --resume) merges
    exactly what is missing.

    A recording without camera poses (a plain color/ + depth/ + intrinsics.txt folder, a bag
    without a pose topic or /tf) is built on poses estimated from its images (--estimate-poses
    does that for any recording); the summary says how far the camera went, the loop closures
    accepted and which frames could not be placed.

    Rooms of one building: the first room placed in a building is its reference frame; place
    the others with --shared-frame, --transform FILE or --align-to ROOM (see `sg3d rooms`).
    """
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
    )

    from sg3d.app.build import BuildError, BuildRequest, prepare, run_build
    from sg3d.app.stores import disk_check
    from sg3d.ingest.detect.choice import with_recognizer

    sequence = _sequence(sequence, sample_name)
    room = _room_name(room, rooms, sequence)
    request = BuildRequest(sequence, room, building, layout, start, stop, transform_file, align_to, shared_frame,
                           bag_options=bag, estimate_poses=estimate_poses, trajectory_out=trajectory_out,
                           wait=wait, rooms=rooms)
    # the flags that tune ABIR/KGE, which the basic presets do not run
    given = [flag_of(k) for k in ("abir_gain", "t_key", "t_anchor") if k in select]
    options = BuildConfig(method=METHODS[method], select=SelectConfig(**select),
                          detect=DetectConfig(with_recognizer(detector, recognizer), score_threshold, quality),
                          chunk_frames=chunk_frames or default_of(BuildConfig, "chunk_frames"))
    progress = Progress(TextColumn("[bold]{task.description:<10}"), BarColumn(), MofNCompleteColumn(),
                        TimeElapsedColumn(), console=Console(stderr=True), disable=as_json, transient=False)
    task = progress.add_task("starting", total=None)

    def on_progress(phase: str, done: int, total: int) -> None:
        if not progress.live.is_started:  # shown once work starts: bad input stays one line
            progress.start()
        progress.update(task, description=phase, completed=done, total=total)

    try:
        # bad input is refused before the store is started
        prepared = prepare(request, options, selection_given=tuple(given))
        summary = run_build(settings.store(), prepared, progress=on_progress,
                            disk_check=disk_check(settings)).as_dict()
    except BuildError as exc:
        raise UserError(str(exc))
    finally:
        if progress.live.is_started:
            progress.stop()
    if as_json:
        click.echo(json.dumps(summary))
    else:
        Console().print(_summary_table(summary))
    if summary["interrupted"]:
        click.echo(f"interrupted: {summary['graph']['merged_chunks']} chunks merged and kept; "
                   f"run the same command again to continue", err=True)
        raise SystemExit(130)


commands = [build]
