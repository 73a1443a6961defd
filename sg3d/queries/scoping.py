"""How far a question reaches: room scopes that templates start from, and the size yardstick."""
from __future__ import annotations

from typing import Optional

from sg3d.core.stored import Row

# Up to this many rooms in scope, templates start from the rooms and read only their objects;
# beyond (a large building), the label index reads fewer records than the rooms' CONTAINS edges.
SCOPE_EXPAND_MAX = 50


def few_rooms(rooms) -> bool:
    """A scope small enough that templates start from its rooms (`*_in_rooms`)."""
    return rooms is not None and len(rooms) <= SCOPE_EXPAND_MAX


# "Big" and "small" compare with the median volume of the label, estimated from at most this many
# stored objects of it (a random sample: ids are random), so the yardstick costs the same in a
# store of 100,000 objects as in one of 500.
MEDIAN_SAMPLE = 500


def by_size(run, rows: list[Row], size: Optional[str]) -> list[Row]:
    """Keep objects above (big) / below (small) the median volume of their own label (exact up to
    MEDIAN_SAMPLE objects of the label, a sample's median beyond)."""
    if size is None:
        return rows
    labels = sorted({r["label"] for r in rows})
    if not labels:
        return rows
    median = {}
    for label in labels:
        rows_m = run.read("vqa_median", label=label, sample=MEDIAN_SAMPLE)
        if rows_m and rows_m[0]["median"] is not None:
            median[label] = float(rows_m[0]["median"])
    keep = (lambda v, m: v > m) if size == "big" else (lambda v, m: v < m)
    return [r for r in rows if r["volume"] is not None and keep(float(r["volume"]), median[r["label"]])]
