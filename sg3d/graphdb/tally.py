"""Per-room object tallies: how many objects of each label (and label + colour) a room holds,
so store-wide counts read one small (:Tally) record per room and label instead of every Object
record (ArcadeDB reads each record an index seek finds, even for count()).

A tally is keyed by room, label and colour ('' = every colour). The merge that creates, relabels,
recolours or folds objects changes the tallies of its room in the same transaction, in the
statement that creates its new objects (`create_objects_and_tallies`: one round trip), so they
commit or roll back with it; merges of one room are serialised by the room lock, so tallies
never conflict across rooms. `rebuild_tallies` recounts them from the
objects (schema migration, bulk loads, or after objects were edited by hand).
"""
from __future__ import annotations

from collections import Counter
from typing import Iterable, Optional

from neo4j import ManagedTransaction

from sg3d.core.stored import Row
from sg3d.graphdb import cypher
from sg3d.graphdb.protocol import GraphStore

ALL_COLOURS = ""


def tally_key(room: str, label: str, colour: str) -> str:
    return f"{room}\x1f{label}\x1f{colour}"


def tally_kind(label: str, colour: str) -> str:
    """The indexed look-up key of a tally, spelt as cypher/vqa_count.cypher builds it."""
    return f"{label}|{colour}"


def tally_deltas(plus: Iterable[tuple[str, Optional[str]]],
                 minus: Iterable[tuple[str, Optional[str]]]) -> Counter:
    """(label, colour) -> net change, each object counted under its colour and under ''."""
    net: Counter = Counter()
    for sign, pairs in ((1, plus), (-1, minus)):
        for label, colour in pairs:
            net[(label, ALL_COLOURS)] += sign
            if colour:
                net[(label, colour)] += sign
    return net


def tally_rows(room: str, counts: Counter) -> list[Row]:
    return [{"key": tally_key(room, label, colour), "kind": tally_kind(label, colour), "room": room,
             "label": label, "colour": colour, "n": int(n)}
            for (label, colour), n in sorted(counts.items()) if n != 0]


# New objects per statement: a local graph of thousands of objects (the 2d-basic preset keeps
# every detection) in one Bolt message of thumbnails is refused by the store.
CREATE_BATCH = 500


def create_objects_and_tallies(tx: ManagedTransaction, room: str, creates: list[Row], plus: Iterable[tuple[str, Optional[str]]],
                               minus: Iterable[tuple[str, Optional[str]]] = ()) -> None:
    """Inside a merge transaction: the room's new objects (cypher/object_create.cypher rows) and
    the tally changes of the whole merge, in one statement (one round trip instead of two) per
    CREATE_BATCH objects, the tallies with the last."""
    tallies = tally_rows(room, tally_deltas(plus, minus))
    batches = [creates[i:i + CREATE_BATCH] for i in range(0, len(creates), CREATE_BATCH)] or [[]]
    for k, batch in enumerate(batches):
        last = k == len(batches) - 1
        if batch or (last and tallies):
            tx.run(cypher.load("object_create"), room=room, rows=batch, tallies=tallies if last else []).consume()


def counted_tallies(rows: Iterable[dict]) -> dict[tuple[str, str, str], int]:
    """(room, label, colour) -> objects, from cypher/tally_source.cypher rows: what the tallies
    should say (each object under its colour and under '')."""
    out: Counter = Counter()
    for r in rows:
        out[(r["room"], r["label"], ALL_COLOURS)] += r["n"]
        if r["colour"]:
            out[(r["room"], r["label"], r["colour"])] += r["n"]
    return {k: n for k, n in out.items() if n != 0}


def stale_tallies(tally_rows_: Iterable[dict], source_rows: Iterable[dict]) -> list[Row]:
    """The tallies (cypher/tally_all.cypher rows) that disagree with a count of the objects
    (cypher/tally_source.cypher rows), missing ones included: [{room, label, colour, stored,
    counted}], sorted. Empty: every tally is right."""
    stored: Counter = Counter()
    for t in tally_rows_:
        stored[(t["room"], t["label"], t["colour"] or ALL_COLOURS)] += int(t["n"] or 0)
    counted = counted_tallies(source_rows)
    return [{"room": k[0], "label": k[1], "colour": k[2], "stored": stored.get(k, 0), "counted": counted.get(k, 0)}
            for k in sorted(set(stored) | set(counted), key=lambda k: tuple(map(str, k)))
            if stored.get(k, 0) != counted.get(k, 0)]


def rebuild_tallies_in_tx(tx: ManagedTransaction, batch: int = 5000) -> int:
    """Inside a write transaction: recount every tally from the Object records as this
    transaction sees them (one scan), replacing the old ones; returns the tallies written."""
    per_room: dict[str, Counter] = {}
    for (room, label, colour), n in counted_tallies(tx.run(cypher.load("tally_source")).data()).items():
        per_room.setdefault(room, Counter())[(label, colour)] = n
    rows = [row for room, counts in per_room.items() for row in tally_rows(room, counts)]
    tx.run(cypher.load("tally_clear")).consume()
    for i in range(0, len(rows), batch):
        tx.run(cypher.load("tally_add"), rows=rows[i:i + batch]).consume()
    tx.run(cypher.load("room_bump_all")).consume()       # counts may read tallies, of any room
    return len(rows)


def rebuild_tallies(store: GraphStore, batch: int = 5000) -> int:
    """Recount every tally from the Object records (one scan, one transaction); returns the
    tallies written."""
    return store.execute_write(lambda tx: rebuild_tallies_in_tx(tx, batch))
