"""`sg3d db check` (the store against `sg3d.app.bounds`): find stored values no reader can use (NaN, Infinity, coordinates beyond the
world extent, an `up` that is not a direction, a counting tally that disagrees with the objects) and repair
them: such an object is removed (with its Appearance and edges), such an `up` is cleared, and
the tallies are recounted, all in ONE transaction (interrupted, nothing of the repair happened
and the next check finds the same)."""
from __future__ import annotations

from dataclasses import dataclass, field

from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore


@dataclass
class CheckReport:
    objects: list[tuple[str, str]] = field(default_factory=list)   # (object id, room id)
    rooms: list[str] = field(default_factory=list)                  # rooms whose up is unusable
    # tallies that disagree with a count of the objects: {room, label, colour, stored, counted}
    tallies: list[dict] = field(default_factory=list)
    repaired: bool = False

    @property
    def clean(self) -> bool:
        return not self.objects and not self.rooms and not self.tallies


def _raw(store: GraphStore, name: str) -> list[dict]:
    """A check template's rows as stored (Store.read would skip the bad ones)."""
    text = cypher.load(name)
    with store.session() as s:
        return s.execute_read(lambda tx: tx.run(text).data())


def object_is_bad(row: dict) -> bool:
    """An object whose position, box or variance is not finite, or lies beyond the world extent."""
    from sg3d.app.bounds import MAX_SIZE_M, within_world
    from sg3d.graphdb.values import has_bad_number

    if has_bad_number(row):
        return True
    position = [row[k] for k in ("x", "y", "z") if row.get(k) is not None] + list(row.get("box_centre") or [])
    size = list(row.get("size") or [])
    return not within_world(position) or any(abs(v) > MAX_SIZE_M for v in size)


def up_is_bad(up) -> bool:
    from sg3d.app.bounds import unit_up

    if up is None:
        return False
    try:
        unit_up(up)
    except (ValueError, TypeError):
        return True
    return False


def repair_in_tx(tx, objects: list[str], rooms: list[str]) -> int:
    """The body of the repair transaction: remove `objects`, clear the up of `rooms`, recount
    every tally. Returns the tallies written."""
    from sg3d.graphdb.tally import rebuild_tallies_in_tx

    for object_id in objects:
        tx.run(cypher.load("node_delete"), id=object_id).consume()
    for room in rooms:
        tx.run(cypher.load("room_up_clear"), room=room).consume()
    return rebuild_tallies_in_tx(tx)


def check_store(store: GraphStore, repair: bool = False) -> CheckReport:
    """What is unusable in `store`, and the tallies that disagree with the objects; with
    `repair`, remove or clear it and recount the tallies (one transaction)."""
    from sg3d.graphdb.tally import stale_tallies

    report = CheckReport(objects=[(r["id"], r["room"]) for r in _raw(store, "check_object_values") if object_is_bad(r)],
                         rooms=[r["id"] for r in _raw(store, "check_room_values") if up_is_bad(r["up"])],
                         tallies=stale_tallies(_raw(store, "tally_all"), _raw(store, "tally_source")))
    if repair and not report.clean:
        ids, rooms = [o for o, _ in report.objects], list(report.rooms)
        store.execute_write(lambda tx: repair_in_tx(tx, ids, rooms))
        report.repaired = True
    return report
