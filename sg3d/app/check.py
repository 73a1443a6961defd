"""`sg3d db check` (the store against `sg3d.app.bounds`): find stored values no reader can use (NaN, Infinity, coordinates beyond the
world extent, an `up` that is not a direction) and repair them: such an object is removed (with
its Appearance and edges, tallies recounted), such an `up` is cleared."""
from __future__ import annotations

from dataclasses import dataclass, field

from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore


@dataclass
class CheckReport:
    objects: list[tuple[str, str]] = field(default_factory=list)   # (object id, room id)
    rooms: list[str] = field(default_factory=list)                  # rooms whose up is unusable
    repaired: bool = False

    @property
    def clean(self) -> bool:
        return not self.objects and not self.rooms


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


def check_store(store: GraphStore, repair: bool = False) -> CheckReport:
    """What is unusable in `store`; with `repair`, remove or clear it (one write per item)."""
    report = CheckReport(objects=[(r["id"], r["room"]) for r in _raw(store, "check_object_values") if object_is_bad(r)],
                         rooms=[r["id"] for r in _raw(store, "check_room_values") if up_is_bad(r["up"])])
    if repair and not report.clean:
        from sg3d.graphdb.tally import rebuild_tallies

        for object_id, _ in report.objects:
            store.write("node_delete", id=object_id)
        for room in report.rooms:
            store.write("room_up_clear", room=room)
        if report.objects:
            rebuild_tallies(store)
        report.repaired = True
    return report
