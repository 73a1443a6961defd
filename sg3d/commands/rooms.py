"""`sg3d rooms`: a building's rooms; `sg3d rooms link A B`: align two rooms and link them;
`sg3d rooms unlink A B`: remove that link; `sg3d rooms delete ROOM`: remove one room; `sg3d rooms
rename OLD NEW`: name a room found in a walk."""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Optional

import click

from sg3d.errors import UserError


@click.group(invoke_without_command=True)
@click.option("--building", default="default", show_default=True, help="Building whose rooms to list.")
@click.option("--json", "as_json", is_flag=True, help="Print the rooms as JSON.")
@click.pass_context
def rooms(ctx: click.Context, building: str, as_json: bool) -> None:
    """List the building's rooms: object counts, the frame each is in, adjacent rooms.

    With a subcommand (`link`, `unlink`, `delete`, `rename`), that subcommand runs instead.
    """
    if ctx.invoked_subcommand is not None:
        return
    from sg3d.app.rooms import building_rooms, frame_words, rooms_json
    from sg3d.app.stores import reader

    rows = building_rooms(reader(ctx.obj), building)
    if as_json:
        click.echo(json.dumps(rooms_json(rows), indent=2))
        return
    if not rows:
        raise UserError(f"building {building!r} has no rooms (build one with `sg3d build`)")
    width = max(len(r["name"]) for r in rows)
    for r in rows:
        adj = f"; adjacent: {', '.join(r['adjacent'])}" if r["adjacent"] else ""
        click.echo(f"{r['name']:<{width}}  {r['objects']:>6} objects  {frame_words(r['to_building'])}{adj}")


@rooms.command("link")
@click.argument("room_a")
@click.argument("room_b")
@click.option("--building", default=None,
              help="Building of the rooms (default: `sg3d rooms --building`, else 'default'; a full "
                   "room id 'building/room' overrides it).")
@click.option("--transform", "transform_file", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="4x4 rigid transform (4 lines of 4 numbers) taking ROOM_B's frame into ROOM_A's; "
                   "skips the alignment.")
@click.option("--tolerance", type=float, default=None,
              help="Metres within which two objects of the rooms are one (default 0.3).")
@click.option("--force", is_flag=True,
              help="Store the alignment even when it rests on too little evidence (fewer than 3 objects "
                   "agreeing in label, colour and size, a small share of what could match, a large residual "
                   "or floors tilted against each other).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.pass_context
def link(ctx: click.Context, room_a: str, room_b: str, building: Optional[str], transform_file: Optional[Path],
         tolerance: Optional[float], force: bool, as_json: bool) -> None:
    """Align ROOM_B to ROOM_A from their shared objects (or a transform file), store both rooms'
    building transforms and link the shared objects (SAME_AS) and the rooms (ADJACENT_TO).

    An alignment without enough independent evidence is refused, with the reason (exit 2);
    --force stores it anyway, `sg3d rooms unlink` removes a link."""
    settings = ctx.obj
    building = _building(ctx, building, "link")
    from sg3d.merge.align import AlignmentError
    from sg3d.graphdb.building import (
        LINK_TOL_M,
        TransformError,
        format_matrix,
        link_rooms,
        load_transform,
    )
    from sg3d.graphdb.values import room_id

    try:
        T = load_transform(transform_file) if transform_file else None
        report = link_rooms(settings.store(), room_id(building, room_a), room_id(building, room_b),
                            transform=T, link_tol_m=LINK_TOL_M if tolerance is None else tolerance, force=force)
    except (AlignmentError, TransformError) as exc:
        raise UserError(str(exc)) from None
    residual = None if math.isnan(report.residual_rms_m) else round(report.residual_rms_m, 4)
    if as_json:
        click.echo(json.dumps({"room_a": report.room_a, "room_b": report.room_b,
                               "transform": report.T.tolist(), "to_building_a": report.to_building_a.tolist(),
                               "to_building_b": report.to_building_b.tolist(), "residual_rms_m": residual,
                               "pairs": report.pairs, "same_as": len(report.same_as),
                               "from_file": report.from_file, "evidence": report.evidence,
                               "share": round(report.share, 3),
                               "up_angle_deg": None if report.up_angle_deg is None else round(report.up_angle_deg, 2),
                               "forced": report.forced}, indent=2))
        return
    source = "from file" if report.from_file else "aligned"
    if report.forced:
        click.echo(f"linked with --force although {report.forced}", err=True)
    click.echo(f"{report.room_b} -> {report.room_a} ({source}):")
    click.echo(format_matrix(report.T))
    click.echo(f"residual: {'n/a' if residual is None else f'{residual:.4f} m'}  pairs: {report.pairs}  "
               f"SAME_AS links: {len(report.same_as)}")


def _building(ctx: click.Context, building: Optional[str], command: str) -> str:
    """The building of a subcommand: its own --building or the group's (given twice: one error)."""
    assert ctx.parent is not None                 # a subcommand: the group's context holds --building
    outer = ctx.parent.params["building"]
    if building is not None and outer != building and \
            ctx.parent.get_parameter_source("building") is not click.core.ParameterSource.DEFAULT:
        raise UserError(f"two buildings given ({outer!r} before {command}, {building!r} after it): "
                        f"give --building once")
    return building or outer


@rooms.command("unlink")
@click.argument("room_a")
@click.argument("room_b")
@click.option("--building", default=None,
              help="Building of the rooms (default: `sg3d rooms --building`, else 'default').")
@click.option("--json", "as_json", is_flag=True, help="Print what was removed as JSON.")
@click.pass_context
def unlink(ctx: click.Context, room_a: str, room_b: str, building: Optional[str], as_json: bool) -> None:
    """Remove the link between ROOM_A and ROOM_B: their ADJACENT_TO edges and the SAME_AS links
    between their objects (one transaction). The rooms keep their building transforms."""
    from sg3d.merge.align import AlignmentError
    from sg3d.graphdb.building import unlink_rooms
    from sg3d.graphdb.values import room_id

    building = _building(ctx, building, "unlink")
    a, b = room_id(building, room_a), room_id(building, room_b)
    try:
        removed = unlink_rooms(ctx.obj.store(), a, b)
    except AlignmentError as exc:
        raise UserError(str(exc)) from None
    if as_json:
        click.echo(json.dumps({"room_a": a, "room_b": b, **removed}))
        return
    click.echo(f"unlinked {b} from {a}: {removed['adjacent']} ADJACENT_TO edge(s) and {removed['same_as']} "
               f"SAME_AS link(s) removed")


@rooms.command("delete")
@click.argument("room")
@click.option("--building", default=None,
              help="Building of the room (default: `sg3d rooms --building`, else 'default').")
@click.option("--yes", is_flag=True, help="Do not ask.")
@click.pass_context
def delete(ctx: click.Context, room: str, building: Optional[str], yes: bool) -> None:
    """Remove ROOM: its objects with their edges, its tallies, merge logs and scans, and the room
    itself; every other room stays as it is (asks first)."""
    from sg3d.app.errors import NotFound
    from sg3d.app.rooms import delete_room
    from sg3d.graphdb.values import room_id

    assert ctx.parent is not None
    building = building or ctx.parent.params["building"]
    rid = room_id(building, room)
    store = ctx.obj.store()
    if not store.read("building_room_get", room=rid):
        raise UserError(f"no room {rid!r} in the store (see `sg3d rooms --building {building}`)")
    if not yes:
        n = store.read("object_count", room=rid)[0]["n"]
        click.confirm(f"delete room {rid} and its {n} objects?", abort=True)
    try:
        done = delete_room(store, building, room)
    except NotFound as exc:
        raise UserError(str(exc)) from None
    click.echo(f"deleted room {done['room']} ({done['objects']} objects)")


@rooms.command("rename")
@click.argument("old")
@click.argument("new")
@click.option("--building", default=None,
              help="Building of the room (default: `sg3d rooms --building`, else 'default').")
@click.option("--room", "recording", default=None,
              help="The recording the room was found in (only when two recordings of the building found "
                   "a room called OLD).")
@click.pass_context
def rename(ctx: click.Context, old: str, new: str, building: Optional[str], recording: Optional[str]) -> None:
    """Call the room found in a walk (`sg3d build --rooms auto`: "room 1", "room 2", ...) OLD by
    the name NEW from now on; questions then know it by NEW ("what is in the room next to NEW?")."""
    from sg3d.app.errors import AppError
    from sg3d.app.places import rename_walk_room

    building = _building(ctx, building, "rename")
    try:
        done = rename_walk_room(ctx.obj.store(), building, old, new, recording)
    except AppError as exc:
        raise UserError(str(exc)) from None
    click.echo(f"renamed {done['old']!r} to {done['new']!r} (found in the walk of {done['room']})")


commands = [rooms]
