"""Keeping the stored relations contradiction-free across merges.

Each local graph arrives contradiction-free (`sg3d.ingest.relate.sdr.vote_relations`), but merging graphs
one after another can still disagree once their nodes are matched: graph 1 says A ON B, graph 2
B ON A. Inside the same merge transaction, `sg3d.graphdb.consistency.resolve_pairs` reads every
edge touching the merged nodes and `resolve_edges`, per pair and family (`sg3d.core.relation_rules`),
keeps only the better-supported statement: the side (A over/in B, B over/in A, side by side) with the larger summed edge count
wins (ties: the higher score), then inside it the form with the larger count (ties: score, then
the more specific). Its edges carry the summed count of its side; the others are deleted. Symmetric edges
stored backwards (a fold can turn one round) are moved to the canonical direction.
"""
from __future__ import annotations

from collections import defaultdict
from typing import Any, Iterable, Mapping

from sg3d.core.model import RelationObservation
from sg3d.core.relation_rules import SYMMETRIC, Statement, edges_of, statement_of
from sg3d.core.stored import Row


def canonical_rows(relations: Iterable[RelationObservation], node_ids: dict[str, str]) -> dict[str, list[Row]]:
    """Relation rows per type for `relation_merge`, in stored form between GLOBAL ids: the
    smaller global id is a symmetric edge's subject (local ids order differently), inverse
    pairs both present, viewpoint relations and self-loops dropped, one row per edge."""
    best: dict[tuple[str, str, str], float] = {}
    for rel in relations:
        st = statement_of(node_ids[rel.subject], rel.predicate, node_ids[rel.object])
        if st is None:
            continue
        for e in edges_of(st, float(rel.score)):
            key = (e.subject, e.predicate, e.object)
            best[key] = max(best.get(key, 0.0), e.score)
    rows: dict[str, list[Row]] = defaultdict(list)
    for (s, p, o), score in sorted(best.items()):
        rows[p].append({"s": s, "o": o, "score": score})
    return rows


def _winner(stated: dict[Statement, tuple[int, float]]) -> tuple[Statement, int]:
    """The better-supported statement and its side's summed count (ON and UNDER the right way
    round are evidence for one side, so the kept edge carries both)."""
    sides: dict[int, list[float]] = defaultdict(lambda: [0, 0.0])
    for st, (count, score) in stated.items():
        sides[st.side][0] += count
        sides[st.side][1] = max(sides[st.side][1], score)
    side = max(sides, key=lambda k: tuple(sides[k]))
    best = max((st for st in stated if st.side == side), key=lambda st: (*stated[st], -st.rank))
    return best, int(sides[side][0])


Edge = tuple[str, str, str]


def resolve_edges(rows: Iterable[Mapping[str, Any]], now: float) -> tuple[dict[str, list[Row]], dict[str, list[Row]]]:
    """The rule of the module docstring over the stored edges of the pairs a merge touched (rows of
    cypher/relation_pair_edges: s, type, o, count, score): the edges to delete and the edges to
    (re)write, per relation type, as rows of cypher/relation_delete and cypher/relation_set."""
    # (family, lo, hi) -> statement -> (count, score); and the stored edges of each pair
    stated: dict[tuple, dict[Statement, tuple[int, float]]] = defaultdict(dict)
    present: dict[tuple, dict[Edge, int]] = defaultdict(dict)
    viewpoint = []
    for r in rows:
        st = statement_of(r["s"], r["type"], r["o"])
        if st is None:
            viewpoint.append((r["s"], r["type"], r["o"]))
            continue
        key = (st.family, st.lo, st.hi)
        count, score = int(r["count"] or 1), float(r["score"] or 0.0)
        old = stated[key].get(st, (0, 0.0))
        # a backwards symmetric twin adds its evidence; inverse twins (ABOVE/BELOW) share one
        twin = st.form in SYMMETRIC
        stated[key][st] = (old[0] + count if twin else max(old[0], count), max(old[1], score))
        present[key][(r["s"], r["type"], r["o"])] = count
    deletes: dict[str, list[Row]] = defaultdict(list)
    writes: dict[str, list[Row]] = defaultdict(list)
    for s, p, o in viewpoint:
        deletes[p].append({"s": s, "o": o})
    for key, by_statement in stated.items():
        best, count = _winner(by_statement)
        score = by_statement[best][1]
        keep = {(e.subject, e.predicate, e.object) for e in edges_of(best, score)}
        edges = present[key]
        if set(edges) == keep and all(edges[k] == count for k in keep):
            continue
        for s, p, o in set(edges) - keep:
            deletes[p].append({"s": s, "o": o})
        for s, p, o in keep:
            writes[p].append({"s": s, "o": o, "score": score, "count": count, "at": now})
    return deletes, writes
