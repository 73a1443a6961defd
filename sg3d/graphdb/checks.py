"""Checks over the stored graph that tests and end-to-end runs assert on."""
from __future__ import annotations

from sg3d.core.model import RELATION_TYPES
from sg3d.core.relation_rules import VIEWPOINT, exclusive_tag_pairs, non_canonical_tags
from sg3d.graphdb.protocol import GraphStore


def relation_contradictions(store: GraphStore, room_id: str) -> dict:
    """How far the stored relations of one room (`building/room`) are from the stored form of
    `sg3d.core.relation_rules`: `contradictory_pairs` (a pair holding two exclusive statements,
    e.g. A ON B and B ON A, or NEXT_TO with NEAR), `non_canonical_symmetric` (NEXT_TO/NEAR
    edges whose subject has the larger id), `viewpoint_edges` (IN_FRONT_OF/BEHIND/LEFT_OF/
    RIGHT_OF, never stored), `pairs` (related pairs) and `examples` ([lo, hi, clashing tags...]).
    All zeros but `pairs` is a consistent graph."""
    rows = store.read("check_contradictions", room=room_id, types=list(RELATION_TYPES),
                      exclusive=exclusive_tag_pairs(), non_canonical=non_canonical_tags(),
                      viewpoint=sorted(VIEWPOINT))
    if not rows:
        return {"pairs": 0, "contradictory_pairs": 0, "non_canonical_symmetric": 0, "viewpoint_edges": 0,
                "examples": []}
    r = rows[0]
    return {"pairs": int(r["pairs"] or 0), "contradictory_pairs": int(r["contradictory_pairs"] or 0),
            "non_canonical_symmetric": int(r["non_canonical_symmetric"] or 0),
            "viewpoint_edges": int(r["viewpoint_edges"] or 0),
            "examples": [list(x) for x in (r["examples"] or []) if x][:10]}
