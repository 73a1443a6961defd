// The building and room a local graph belongs to, and the room's lock: the first write of every
// merge transaction updates the room node, so two merges of one room conflict and the store runs
// them one after the other (the loser is retried and sees the winner's objects). It also bumps the
// room's revision, in the same transaction as the merge or publish it belongs to, so a revision
// read names every write committed before it (the answer cache of `sg3d serve` is keyed by it);
// `born` (when the room was made) tells a room made again after a delete from the one before.
// The revision it returns names the transaction's new nodes (sg3d/merge/ids.py).
MERGE (b:Building {id: $building})
ON CREATE SET b.name = $building
MERGE (r:Room {id: $room})
ON CREATE SET r.name = $name, r.building = $building, r.born = timestamp()
SET r.up = coalesce($up, r.up), r.merges = coalesce(r.merges, 0) + 1, r.revision = coalesce(r.revision, 0) + 1
MERGE (b)-[:HAS_ROOM]->(r)
RETURN r.revision AS revision
