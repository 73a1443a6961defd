"""Room and building names matched as object names are: case, spaces and small typos.

"living room" finds the room stored as `livingroom`, "Kitchen" finds `kitchen`, "kitchn" finds
`kitchen`. Spacing, case, hyphens and underscores never matter; a typo (rapidfuzz, the edit
distance of sg3d/queries/reader/typos.py) is fixed only for a name that is not itself a known or
common word, so "in the box" never finds a room called "bo". The answer says what was matched.
"""
from __future__ import annotations

import re
from typing import Iterable, Optional

from sg3d.queries.reader.typos import is_word, max_edits


def squeezed(name: str) -> str:
    """The name without case, spaces, hyphens, underscores or punctuation: "Living-Room" -> "livingroom"."""
    return re.sub(r"[\W_]+", "", name.lower())


def match_name(asked: str, stored: Iterable[str], vocab: frozenset = frozenset()) -> Optional[str]:
    """The one stored name `asked` means, or None: the same letters once squeezed (also without
    a trailing "room": "the study room" -> `study`), else the only name within `max_edits` of it
    when `asked` is not a known word (`vocab`) or a common English word."""
    names = sorted(set(stored))
    want = squeezed(asked)
    if not want:
        return None
    for key in (want, want[:-4] if want.endswith("room") and len(want) > 4 else None):
        hits = [n for n in names if key and squeezed(n) == key]
        if len(hits) == 1:
            return hits[0]
    if any(is_word(w, vocab) for w in asked.lower().split()):
        return None
    limit = max_edits(want)
    if not limit:
        return None
    from rapidfuzz.distance import DamerauLevenshtein

    scored = [(DamerauLevenshtein.distance(want, squeezed(n)), n) for n in names]
    close = [(d, n) for d, n in scored if d <= limit]
    if not close:
        return None
    best = min(d for d, _ in close)
    winners = [n for d, n in close if d == best]
    return winners[0] if len(winners) == 1 else None


def read_as(asked: str, matched: str, what: str = "room") -> Optional[str]:
    """The note an answer carries when a name was matched loosely; None when written as stored."""
    if asked.lower() == matched.lower():
        return None
    return f"{what} '{asked}' read as '{matched}'"
