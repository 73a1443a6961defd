"""`sg3d frames SEQUENCE`: read a posed RGB-D sequence, reject blurry frames (ABIR) and extract
keyframe groups (KGE); report what would go on to detection, and how fast."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import click

from sg3d.commands.bag_options import bag_options
from sg3d.commands.config_options import config_options
from sg3d.errors import UserError
from sg3d.ingest.config import SelectConfig

if TYPE_CHECKING:
    from sg3d.ingest.readers.base import Sequence
    from sg3d.ingest.select.selection import SelectionParams

SHEET_PAIRS = 24
SHEET_FACTOR = 4   # thumbnails at 1/4 of the colour size (160x120 for 640x480)


@click.command("frames")
@click.argument("sequence", type=click.Path(path_type=Path))
@click.option("--layout", default=None, metavar="NAME",
              help="7scenes (also 3DMatch), tum, scannet or open3d. Default: detected from the files.")
@config_options(SelectConfig, ("abir_gain", "abir_offset", "abir_alpha", "t_key", "t_anchor"), "select")
@click.option("--limit", type=click.IntRange(min=1), default=None, metavar="N", help="Read at most N frames.")
@click.option("--step", type=click.IntRange(min=1), default=1, show_default=True, help="Read every STEP-th frame.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output on stdout.")
@click.option("--sheet", type=click.Path(dir_okay=False, path_type=Path), default=None, metavar="PNG",
              help="Write a contact sheet: frames rejected as blurry beside the last sharp frame before each.")
@bag_options
def frames_command(sequence: Path, layout: Optional[str], select: dict[str, Any], limit: Optional[int], step: int,
                   as_json: bool, sheet: Optional[Path], bag: dict) -> None:
    """Blur rejection and keyframe groups over SEQUENCE (a sequence folder or a ROS bag)."""
    from sg3d.ingest.readers import SequenceError, open_sequence

    params = _params(select)
    try:
        seq = open_sequence(sequence, layout=layout, **bag)
    except SequenceError as exc:
        raise UserError(str(exc)) from None
    if not seq.has_poses():     # keyframe groups compare camera poses
        raise UserError(f"no pose source in {sequence}: keyframe groups need camera poses; "
                        f"`sg3d build` estimates them from the images")
    stop = len(seq) if limit is None else min(len(seq), limit * step)
    run = _select(seq, params, stop, step, keep_pairs=sheet is not None, quiet=as_json)
    if sheet is not None:
        _write_sheet(seq, run.pairs, sheet)
    choice = run.choice
    params_out = {k: getattr(params, k) for k in ("abir_alpha", "abir_gain", "abir_offset", "t_key", "t_anchor")}
    if as_json:
        click.echo(json.dumps({"sequence": str(sequence), "layout": seq.layout, "frames_in_sequence": len(seq),
                               **choice.stats.as_dict(), "params": params_out,
                               "sources": getattr(seq, "sources", None),
                               "skipped_frames": [{"frame": n, "reason": r} for n, r in seq.skipped],
                               "groups_frames": choice.groups, "detected_frames": choice.detected,
                               "sheet": str(sheet) if sheet else None}))
        return
    _print_report(sequence, seq, params_out, choice, sheet, len(run.pairs))


def _params(select: dict[str, Any]) -> SelectionParams:
    """The selection parameters, each given one or its default (as `sg3d build` uses them); a value
    out of range is one line on stderr."""
    from sg3d.ingest.select.abir import ABIR
    from sg3d.ingest.select.kge import KeyframeGrouper

    params = SelectConfig(**select).params
    try:
        ABIR(params.abir_alpha, params.abir_gain, params.abir_offset)
        KeyframeGrouper(params.t_key, params.t_anchor)
    except ValueError as exc:
        raise UserError(str(exc)) from None
    return params


@dataclass
class _Selection:
    """What one pass of frame selection saw."""
    choice: Any = None
    pairs: list = field(default_factory=list)       # (blurry index, decision, sharp index, decision)


def _select(seq: Sequence, params, stop: int, step: int, keep_pairs: bool, quiet: bool) -> _Selection:
    """`choose_detected_frames` over frames 0..stop (every `step`-th), with a progress bar on
    stderr; `keep_pairs`: remember each blurry frame beside the last sharp one (the contact sheet)."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
    )

    from sg3d.ingest.select.selection import choose_detected_frames

    run = _Selection()
    last_sharp: list = [None, None]

    def on_frame(frame, decision, role):
        progress.advance(task)
        if not keep_pairs or decision is None:
            return
        if role == "blurry":
            if last_sharp[0] is not None:
                run.pairs.append((frame.index, decision, last_sharp[0], last_sharp[1]))
        elif role != "skipped":
            last_sharp[:] = [frame.index, decision]

    console = Console(stderr=True)
    with Progress(TextColumn("[bold]frames"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                  console=console, transient=True, disable=quiet and not console.is_terminal) as progress:
        task = progress.add_task("frames", total=len(range(0, stop, step)))
        run.choice = choose_detected_frames(seq, 0, stop, step, params=params, on_frame=on_frame)
    return run


def _print_report(sequence: Path, seq: Sequence, params: dict, choice, sheet: Optional[Path], n_pairs: int) -> None:
    """The human-readable report on stdout."""
    from rich.console import Console

    from sg3d.ingest.select import coverage

    stats, detected = choice.stats, choice.detected
    skipped, groups = seq.skipped, choice.groups
    out = Console()
    out.print(f"[bold]{sequence}[/] ({seq.layout}, {len(seq)} frames, {seq.image_size[0]}x{seq.image_size[1]})")
    rows = [
        ("frames read", f"{stats.read}", f"of {stats.frames} asked for"),
        ("skipped", f"{stats.skipped}", "bad frames, listed below" if skipped else ""),
        ("blurry (ABIR)", f"{stats.blurry}", f"alpha {params['abir_alpha']}, gain {params['abir_gain']}, "
                                              f"offset {params['abir_offset']}"),
        ("keyframes", f"{stats.keyframes}", f"t_key {params['t_key']}"),
        ("anchors", f"{stats.anchors}", f"t_anchor {params['t_anchor']}"),
        ("groups", f"{stats.groups}", "frames per group: " + " ".join(str(len(g)) for g in groups[:20])
         + (" ..." if len(groups) > 20 else "")),
        ("keyframes+anchors", f"{100 * stats.fraction_kept:.1f} %", f"{stats.kept} of {stats.read} frames read"),
        ("detected by build", f"{len(detected)}", f"keyframes and anchors + {choice.coverage} "
                                                   f"frames with new viewpoints ({coverage.DEFAULT_FRACTION:.0%} "
                                                   f"of the sharp frames, at least {coverage.MIN_FRAMES}), each the "
                                                   f"sharpest of its {coverage.SNAP_WINDOW}-frame window"),
        ("time", f"{stats.seconds:.2f} s", f"{stats.frames_per_second:.0f} frames/s"),
    ]
    for role, what in (getattr(seq, "sources", None) or {}).items():
        out.print(f"  {role:<18} {what}", soft_wrap=True, highlight=False, markup=False)
    for label, value, note in rows:
        out.print(f"  {label:<18} {value:>9}   [dim]{note}[/]")
    for name, reason in skipped[:10]:
        out.print(f"  [yellow]skipped[/] {name}: {reason}")
    if len(skipped) > 10:
        out.print(f"  [yellow]... and {len(skipped) - 10} more skipped frames[/]")
    if sheet is not None:
        out.print(f"  contact sheet: {sheet} ({min(n_pairs, SHEET_PAIRS)} blurry/sharp pairs)")


def _write_sheet(seq: Sequence, pairs, path: Path) -> None:
    """Rows of [rejected as blurry | last sharp frame before it], each labelled V and threshold."""
    import cv2
    import numpy as np

    from sg3d.ingest.readers.frames import FrameError

    if len(pairs) > SHEET_PAIRS:  # spread over the whole run, not the first burst only
        pick = np.linspace(0, len(pairs) - 1, SHEET_PAIRS).round().astype(int)
        pairs = [pairs[i] for i in pick]
    w, h = seq.image_size
    tw, th = max(1, w // SHEET_FACTOR), max(1, h // SHEET_FACTOR)
    label_h, gap, per_row = 16, 8, 3

    def tile(index: int, decision, blurry: bool):
        try:
            img = seq.frame(index, lazy=True).preview(SHEET_FACTOR)
            img = cv2.resize(img, (tw, th), interpolation=cv2.INTER_AREA)
        except FrameError:
            img = np.zeros((th, tw, 3), np.uint8)
        canvas = np.full((th + label_h, tw, 3), 255, np.uint8)
        canvas[label_h:] = img
        text = f"#{index} V={decision.variance:.0f} {'<' if blurry else '>='} t={decision.threshold:.0f}"
        colour = (0, 0, 200) if blurry else (0, 140, 0)
        cv2.putText(canvas, text, (2, 12), cv2.FONT_HERSHEY_SIMPLEX, 0.38, colour, 1, cv2.LINE_AA)
        return canvas

    cells = []
    for bi, bd, si, sd in pairs:
        pair = np.hstack([tile(bi, bd, True), np.full((th + label_h, 2, 3), 0, np.uint8), tile(si, sd, False)])
        cells.append(pair)
    header_h = 24
    cell_w = 2 * tw + 2
    rows = max(1, (len(cells) + per_row - 1) // per_row)
    sheet = np.full((header_h + rows * (th + label_h + gap), per_row * (cell_w + gap), 3), 255, np.uint8)
    title = ("rejected as blurry (left, red) | last sharp frame before it (right, green)" if cells
             else "no frame was rejected as blurry")
    cv2.putText(sheet, title, (4, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
    for k, cell in enumerate(cells):
        r, c = divmod(k, per_row)
        y = header_h + r * (th + label_h + gap)
        x = c * (cell_w + gap)
        sheet[y:y + cell.shape[0], x:x + cell.shape[1]] = cell
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise UserError(f"--sheet writes a PNG; give a file name ending in .png, not {path.name}")
    if not path.parent.exists():
        raise UserError(f"cannot write the contact sheet: folder {path.parent} does not exist")
    if not cv2.imwrite(str(path), sheet):
        raise UserError(f"cannot write the contact sheet to {path}")


commands = [frames_command]
