"""`sg3d db start|stop|status|reset|check|rebuild-tallies`: the store's lifecycle and repair."""
from __future__ import annotations

import json
import time
from typing import TYPE_CHECKING, NoReturn

import click

from sg3d.errors import UserError

if TYPE_CHECKING:
    from sg3d.settings import Settings


def _server(settings: Settings):
    from sg3d.graphdb.embedded import EmbeddedServer

    if not settings.embedded:
        raise UserError("`sg3d db start|stop|status` manage the embedded store; drop --uri/SG3D_URI "
                        "(a Neo4j server is managed by its own tools, see docker-compose.yml)")
    return EmbeddedServer(settings.embedded_home())


@click.group()
def db() -> None:
    """Manage the embedded graph store (started on demand by every command that needs it)."""


@db.command()
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
@click.pass_obj
def status(settings: Settings, as_json: bool) -> None:
    """Say whether the embedded store runs, where, and since when."""
    server = _server(settings)
    st = server.status()
    data = {"running": st.running, "home": str(server.home), "recovered_stale": st.recovered_stale}
    if st.info:
        data.update(pid=st.info.pid, uri=st.info.uri, database=st.info.database,
                    uptime_s=round(time.time() - st.info.started_at, 1))
    if as_json:
        click.echo(json.dumps(data))
        return
    if st.recovered_stale:
        click.echo("cleared the leftovers of a store that had stopped without shutting down")
    if not st.running:
        click.echo(f"not running (home {server.home})")
    elif st.info is None:
        click.echo(f"starting (home {server.home})")
    else:
        click.echo(f"running: {st.info.uri} database {st.info.database} pid {st.info.pid} "
                   f"up {data['uptime_s']:.0f} s (home {server.home})")


@db.command()
@click.pass_obj
def start(settings: Settings) -> None:
    """Start the embedded store (no-op if it already runs)."""
    server = _server(settings)
    st = server.status()
    if st.running and st.info:
        click.echo(f"already running: {st.info.uri} pid {st.info.pid}")
        return
    lost = server.accept_lost()
    if lost:
        click.echo(f"starting an empty store: {lost}", err=True)
    t0 = time.monotonic()
    info = server.start()
    settings.store().ensure_schema()
    click.echo(f"started: {info.uri} database {info.database} pid {info.pid} in {time.monotonic() - t0:.1f} s")


@db.command()
@click.pass_obj
def stop(settings: Settings) -> None:
    """Stop the embedded store cleanly. It stays stopped for `sg3d serve` and `sg3d mcp` (they
    answer "the store was stopped") until `sg3d db start` or another command starts it."""
    server = _server(settings)
    stopped = server.stop()          # EmbeddedStoreError: says why it cannot
    server.mark_stopped()
    click.echo("stopped" if stopped else "not running")


@db.command()
@click.option("--yes", is_flag=True, help="Do not ask.")
@click.pass_obj
def reset(settings: Settings, yes: bool) -> None:
    """Delete every node and edge of the store (asks first)."""
    if not yes:
        click.confirm(f"delete the whole graph in {settings.uri or 'the embedded store'}?", abort=True)
    settings.store().wipe()
    click.echo("store emptied")


@db.command()
@click.option("--repair", is_flag=True, help="Remove the unusable objects and clear unusable up directions.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
@click.pass_obj
def check(settings: Settings, repair: bool, as_json: bool) -> None:
    """Check the store: the embedded store's own integrity (ArcadeDB's CHECK DATABASE: pages,
    records, edges, indexes; whether its database folder is still there; each unique index against
    the records), exit status 1 when it is damaged; then stored values no reader can use (NaN,
    Infinity, positions beyond the world extent, an up that is no direction) and tallies that
    disagree with the objects, exit status 1 when found; --repair removes such objects, clears such
    up directions and recounts the tallies (exit status 0)."""
    from sg3d.app.check import check_store, index_problems, integrity_problems, record_problems

    damage: list[str] = []
    server = _server(settings) if settings.embedded else None
    if server is not None:
        lost = server.lost()
        if lost:
            _damaged([lost + "; what it held is gone (`sg3d db start` starts an empty store)"], as_json)
    store = settings.store()
    store.ensure_schema()
    if server is not None:
        damage = integrity_problems(server.check_database(), server.database_dir)
    damage += record_problems(store)     # before the indexes: a damaged dictionary explains their disagreement
    if server is not None:
        damage += index_problems(server.sql)
    if damage:
        _damaged(damage, as_json)
    report = check_store(store, repair=repair)
    data = {"objects": [{"id": i, "room": r} for i, r in report.objects], "rooms": report.rooms,
            "tallies": report.tallies, "repaired": report.repaired, "integrity": "clean" if server else "not checked"}
    if as_json:
        click.echo(json.dumps(data))
    elif report.clean:
        click.echo("the store holds no unusable values" + ("; its files passed the store's CHECK DATABASE "
                                                             "and its unique indexes agree with the records"
                                                             if server else ""))
    else:
        _found(report)
    if not report.clean and not report.repaired:
        raise SystemExit(1)     # found, not repaired: a script must not read it as a clean store


def _found(report) -> None:
    verb = "removed" if report.repaired else "found"
    click.echo(f"{verb} {len(report.objects)} object(s) with unusable numbers, "
               f"{'cleared' if report.repaired else 'found'} {len(report.rooms)} unusable room up direction(s), "
               f"{'recounted' if report.repaired else 'found'} {len(report.tallies)} tally(ies) that disagree "
               f"with the objects" + ("" if report.repaired else "; `sg3d db check --repair` fixes them"))
    for object_id, room in report.objects[:20]:
        click.echo(f"  object {object_id} (room {room})")
    for room in report.rooms[:20]:
        click.echo(f"  room {room}: up")
    for t in report.tallies[:20]:
        click.echo(f"  tally {t['label']} ({t['colour']}) in {t['room']}: {t['stored']} stored, {t['counted']} counted")


def _damaged(damage: list[str], as_json: bool) -> NoReturn:
    """Report a damaged store and exit 1 (a damaged store is no bad input, and no repair here
    can bring back what it lost)."""
    if as_json:
        click.echo(json.dumps({"integrity": "damaged", "damage": damage}))
    else:
        click.echo(f"the store is damaged: {damage[0]}" + (f" (and {len(damage) - 1} more)" if len(damage) > 1 else ""))
        for line in damage[1:20]:
            click.echo(f"  {line}")
    raise SystemExit(1)


@db.command("rebuild-tallies")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
@click.pass_obj
def rebuild_tallies_cmd(settings: Settings, as_json: bool) -> None:
    """Recount the per-room tallies that counting questions read from the Object records (after
    objects were edited with `sg3d cypher --write`; a schema upgrade recounts them itself)."""
    from sg3d.graphdb.tally import rebuild_tallies

    store = settings.store()
    store.ensure_schema()
    t0 = time.monotonic()
    n = rebuild_tallies(store)
    objects = store.read("object_total")[0]["n"]
    data = {"tallies": n, "objects": objects, "seconds": round(time.monotonic() - t0, 2)}
    if as_json:
        click.echo(json.dumps(data))
    else:
        click.echo(f"recounted {n} tallies from {objects} objects in {data['seconds']:.1f} s")


commands = [db]
