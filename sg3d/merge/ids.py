"""Node ids from what a merge knows, so the same frames give the same graph on any machine.

A merge (or live publish) runs in one transaction whose first write bumps its room's revision
(cypher/room_ensure): the (room id, revision after the bump) pair names that transaction among
every write the room has seen, and a second merge of the room reads a later revision. An id made
from it and the observation's index in the local graph is therefore the same in every build of
the same frames into a fresh store, and new in a later merge into the same store. A room deleted
and made again starts its revisions over, but its objects went with it, so nothing is left to
collide with. The room id is made of the building's and the room's names, never of a path of the
machine that built it.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass

# hex digits of the hash an id keeps: 64 bits, as the random ids they replace
ID_HEX_DIGITS = 16


def _digest(*parts: object) -> str:
    return hashlib.sha256("\x1f".join(str(p) for p in parts).encode()).hexdigest()


@dataclass(frozen=True)
class MergeIds:
    """The ids one merge gives the nodes it makes: its room and that room's revision in the merge
    transaction (after the merge's own bump)."""
    room: str
    revision: int

    def object_id(self, index: int) -> str:
        """Rule "the same frames give the same ids": the new Object made from observation `index` of
        the local graph is "o-" and the first ID_HEX_DIGITS hex digits of SHA-256(room id,
        revision, index). Unique within a store: (room, revision) is one transaction's."""
        return "o-" + _digest(self.room, self.revision, index)[:ID_HEX_DIGITS]

    def scan_id(self) -> str:
        """The scan of a local graph that names none (no key, no scan): "merge-" and 12 hex digits
        of SHA-256(room id, revision), the one scan this merge is."""
        return "merge-" + _digest(self.room, self.revision)[:12]
