"""`sg3d map`: the room's graph grows while the camera moves (a folder being written)."""
from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import click

from sg3d.commands.names import checked_name
from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings


@click.command(name="map")
@click.argument("source", type=click.Path(path_type=Path))
@click.option("--room", required=True, callback=checked_name, help="Room the live graph is written to.")
@click.option("--building", default="default", show_default=True, callback=checked_name,
              help="Building the room belongs to.")
@click.option("--layout", type=click.Choice(["7scenes", "3dmatch", "tum", "scannet", "open3d", "plain"]), default=None,
              help="Layout of the frames written into SOURCE (default: detected from the first frames).")
@click.option("--publish-every", type=float, default=1.0, show_default=True,
              help="Seconds between publishes of the graph to the store (each one transaction).")
@click.option("--stop-when-idle", type=float, default=None, metavar="SECONDS",
              help="End when no new frame came for this long (default: run until Ctrl-C).")
@click.option("--resume", is_flag=True,
              help="Map into a room an earlier `sg3d map` left (killed or stopped); its objects keep their ids.")
@click.option("--wait", is_flag=True,
              help="When another build, map or ingest is writing ROOM, wait for it instead of refusing.")
@click.option("--detector", default=None, metavar="NAME|MODEL.onnx",
              help="Detector: ssd-mobilenet-v2-coco (default) or your own ONNX model (labels file beside it).")
@click.option("--trajectory-out", type=click.Path(path_type=Path, dir_okay=False), default=None,
              help="A source without poses: write the camera poses tracked online here (TUM format).")
@click.option("--rooms", type=click.Choice(["auto"]), default=None,
              help="auto: also find the rooms the walk goes through, as `sg3d build --rooms auto` does; they "
                   "grow with the walk and keep their ids and names across publishes.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON at the end (no live line).")
@click.pass_obj
def map_cmd(settings: Settings, source: Path, room: str, building: str, layout: Optional[str], publish_every: float,
            stop_when_idle: Optional[float], resume: bool, wait: bool, detector: Optional[str],
            trajectory_out: Optional[Path], rooms: Optional[str], as_json: bool) -> None:
    """Follow SOURCE and keep ROOM's scene graph in the store current while frames arrive. SOURCE
    is a folder that frames are being written into (any layout `sg3d build` reads), `realsense`,
    `realsense:SERIAL` or `realsense:FILE.bag|.db3` (a RealSense camera or recording; pip install
    'sg3d[live]'), or an MCAP file (or ROS 2 bag folder) that `ros2 bag record -s mcap` is writing.
    Sources without poses (a folder without pose files, a RealSense, an MCAP without /tf or
    odometry) are tracked online (--trajectory-out writes the tracked poses).

    Every frame is judged as it arrives (blur, keyframes), the chosen ones are detected, and the
    room's graph is recomputed from all evidence so far and published at most every
    --publish-every seconds, as one transaction with stable object ids: `sg3d ask` and
    `sg3d serve` answer from it meanwhile. When the source ends (--stop-when-idle), the last
    publish is the graph `sg3d build SOURCE` gives. Ctrl-C stops and keeps the last publish;
    --resume continues into the same room.
    """
    from rich.console import Console

    from sg3d.app.build import BuildError
    from sg3d.app.mapping import MapError, MapRequest, map_room
    from sg3d.ingest.config import BuildConfig, DetectConfig

    options = BuildConfig(detect=DetectConfig(detector=detector)) if detector else BuildConfig()
    console = Console(stderr=True)

    def on_update(u: dict) -> None:
        if not as_json:
            print_update(console, u)

    req = MapRequest(source, room, building, layout, publish_every, stop_when_idle, resume, wait, trajectory_out,
                     rooms)
    try:
        summary = map_room(settings.store(), req, options, on_update=on_update).as_dict()
    except (MapError, BuildError) as exc:
        raise UserError(str(exc))
    if as_json:
        click.echo(json.dumps(summary))
    else:
        lat = summary["latency_s"]
        f = summary["frames"]
        click.echo(f"{summary['state']}: {summary['room']} holds {summary['objects']} objects, {summary['relations']} "
                   f"relations; {f['received']} frames, {f['detected']} detected, {f['skipped_behind'] + f['jumped']} skipped "
                   f"while behind; latency p50 {lat.get('p50')} s, p95 {lat.get('p95')} s")
        for kind in f["skipped_by_reason"]:
            shown = ", ".join(s["frame"] for s in kind["frames"]) + (", ..." if kind["count"] > len(kind["frames"]) else "")
            click.echo(f"  skipped {kind['count']} bad frame(s), {kind['reason']}: {shown}")
    if summary["state"] == "stopped":
        raise SystemExit(130)


commands = [map_cmd]


def print_update(console, u: dict) -> None:
    """One line per publish, its state first ('[live] frames 412, ...'); not read as rich markup,
    which took '[live]' for a style and printed nothing of it."""
    p50 = u.get("latency_p50")
    console.print(f"[{u['state']}] frames {u['frames']}, detected {u['detected']}, objects {u['objects']} "
                  f"(+{u['created']} -{u['removed']})" + (f", latency p50 {p50:.2f} s" if p50 is not None else ""),
                  highlight=False, markup=False)
