"""`sg3d db check` (the store against `sg3d.app.bounds`): find stored values no reader can use (NaN, Infinity, coordinates beyond the
world extent, an `up` that is not a direction, a counting tally that disagrees with the objects) and repair
them: such an object is removed (with its Appearance and edges), such an `up` is cleared, and
the tallies are recounted, all in ONE transaction (interrupted, nothing of the repair happened
and the next check finds the same)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Optional

from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore


@dataclass
class CheckReport:
    objects: list[tuple[str, str]] = field(default_factory=list)   # (object id, room id)
    rooms: list[str] = field(default_factory=list)                  # rooms whose up is unusable
    # tallies that disagree with a count of the objects: {room, label, colour, stored, counted}
    tallies: list[Row] = field(default_factory=list)
    repaired: bool = False

    @property
    def clean(self) -> bool:
        return not self.objects and not self.rooms and not self.tallies


def _raw(store: GraphStore, name: str) -> list[Row]:
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


def up_is_bad(up: Any) -> bool:
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


# Counters of ArcadeDB's CHECK DATABASE result that name damage (any non-zero one does).
DAMAGE_COUNTS = ("totalErrors", "totalCorruptedRecords", "totalUndecodableRecords", "invalidLinks",
                 "edgesMissingOutReference", "edgesMissingInReference", "missingReferenceBack",
                 "danglingPlaceholderPointers", "unreachableEdgeRecords", "distinctMissingReferences",
                 "totalConstraintViolations", "crossLinkedChunks", "orphanedChunks")
# Lists of that result that name damaged parts.
DAMAGE_LISTS = ("corruptedIndexes", "corruptedRecords", "undecodableRecords", "unreadableStripeDirectories",
                "corruptedTimeSeries", "constraintViolatingRecords")


def integrity_problems(result: dict, database_dir=None) -> list[str]:
    """What a CHECK DATABASE `result` (`EmbeddedServer.check_database`) names as damage, one line
    each ("totalCorruptedRecords: 3", "corruptedIndexes: Object[id]", and its warnings); also a
    database folder `database_dir` that is not there. Empty: the store's files are sound."""
    from pathlib import Path

    problems = []
    if database_dir is not None and not Path(database_dir).is_dir():
        problems.append(f"the store's database folder {database_dir} is gone while the store runs: "
                        f"what it held is lost at its stop")
    for key in DAMAGE_COUNTS:
        n = result.get(key) or 0
        if isinstance(n, (int, float)) and n > 0:
            problems.append(f"{key}: {n:g}")
    for key in DAMAGE_LISTS:
        items = result.get(key) or []
        if items:
            shown = ", ".join(str(x)[:80] for x in list(items)[:5])
            problems.append(f"{key}: {shown}" + (f" (+{len(items) - 5})" if len(items) > 5 else ""))
    if problems:     # the warnings say where; alone they are no damage
        problems += [f"warning: {str(w)[:200]}" for w in list(result.get("warnings") or [])[:10]]
    return problems


def record_problems(store: GraphStore) -> list[str]:
    """Records missing a property sg3d always writes (`check_required_properties`), one line per
    kind: what a damaged dictionary of property names looks like from outside (the store's own
    CHECK DATABASE passes it, while every question about the room is answered wrong)."""
    rows = _raw(store, "check_required_properties")
    if not rows:
        return []
    r = rows[0]
    out = []
    for kind, total, missing, what in (("Object", "objects", "objects_missing", "id, room or label"),
                                       ("Room", "rooms", "rooms_missing", "id"),
                                       ("Tally", "tallies", "tallies_missing", "room or label")):
        if r.get(missing):
            out.append(f"{r[missing]} of {r[total]} {kind} records have no {what} (the store's dictionary of "
                       f"property names is damaged?)")
    return out


def unique_keys() -> list[tuple[str, str]]:
    """(label, property) of every unique constraint of sg3d's schema (`cypher/schema.cypher`)."""
    import re

    return re.findall(r"FOR \(\w+:(\w+)\) REQUIRE \w+\.(\w+) IS UNIQUE", cypher.load("schema"))


def _index_vs_records(name: str, entries: Optional[list[Row]], records: list[Row]) -> list[str]:
    """What disagrees between one unique index's `entries` ({key: [k], rid}; None: the index is
    missing) and the `records` ({key, rid}) of its type: keys held by several records, records the
    index does not hold, entries that point to no such record."""
    out = []
    holders: dict = {}
    for r in records:
        holders.setdefault(r["key"], []).append(r["rid"])
    for key, rids in holders.items():
        if len(rids) > 1:
            out.append(f"{name}: {key!r} is held by {len(rids)} records ({', '.join(rids[:5])}); "
                       f"a unique key repeats")
    if entries is None:
        return [f"the unique index {name} is missing from the store (its file is damaged): "
                f"duplicates are no longer refused"] + out
    indexed = {((e.get("key") or [None])[0], e.get("rid")) for e in entries}
    stored = {(r["key"], r["rid"]) for r in records}
    for what, pairs in (("records the index does not hold", stored - indexed),
                        ("index entries that point to no such record", indexed - stored)):
        if pairs:
            shown = ", ".join(f"{k!r} {rid}" for k, rid in sorted(pairs, key=str)[:5])
            out.append(f"{name}: {len(pairs)} {what} ({shown})")
    return out


def index_problems(sql: Callable[[str], list[Row]]) -> list[str]:
    """Every unique index of sg3d's schema compared with the records of its type (`sql`: the
    store's own SQL, `EmbeddedServer.sql`): the index is there, holds one entry per record with
    the record's key, and no key repeats among the records. One line per disagreement; empty: the
    indexes agree with the records. (A damaged index page passes the store's CHECK DATABASE, and
    a store whose id index lost entries accepts duplicate ids.)"""
    from sg3d.graphdb.embedded import EmbeddedStoreError

    present = {r.get("name") for r in sql("SELECT name FROM schema:indexes")}
    out = []
    for label, prop in unique_keys():
        name = f"{label}[{prop}]"
        records = sql(f"SELECT @rid AS rid, `{prop}` AS key FROM `{label}` WHERE `{prop}` IS NOT NULL")
        try:
            entries = sql(f"SELECT key, rid FROM index:`{name}`") if name in present else None
        except EmbeddedStoreError as exc:
            out.append(f"the unique index {name} cannot be read: {exc}")
            continue
        out += _index_vs_records(name, entries, records)
    return out
