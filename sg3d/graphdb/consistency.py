"""The stored relations kept contradiction-free across merges: the rule is
`sg3d.merge.consistency.resolve_edges`; this reads the edges it judges and writes its verdict, inside
the merge transaction."""
from __future__ import annotations

import time
from typing import Iterable

from neo4j import ManagedTransaction

from sg3d.core.model import RELATION_TYPES
from sg3d.graphdb import cypher
from sg3d.merge.consistency import resolve_edges


def resolve_pairs(tx: ManagedTransaction, ids: Iterable[str]) -> dict[str, int]:
    """Make the relations of every pair touching `ids` contradiction-free and canonical
    (`resolve_edges`). Returns how many edges were deleted and (re)written."""
    ids = sorted(set(ids))
    if not ids:
        return {"deleted": 0, "written": 0}
    rows = tx.run(cypher.load("relation_pair_edges"), ids=ids, types=list(RELATION_TYPES))
    deletes, writes = resolve_edges(rows, time.time())
    for rel_type, batch in sorted(deletes.items()):
        tx.run(cypher.render("relation_delete", rel_type), rows=batch).consume()
    for rel_type, batch in sorted(writes.items()):
        tx.run(cypher.render("relation_set", rel_type), rows=batch).consume()
    return {"deleted": sum(map(len, deletes.values())), "written": sum(map(len, writes.values()))}
