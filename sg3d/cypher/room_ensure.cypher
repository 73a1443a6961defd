// The building and room a local graph belongs to, and the room's lock: the first write of every
// merge transaction updates the room node, so two merges of one room conflict and the store runs
// them one after the other (the loser is retried and sees the winner's objects).
MERGE (b:Building {id: $building})
ON CREATE SET b.name = $building
MERGE (r:Room {id: $room})
ON CREATE SET r.name = $name, r.building = $building
SET r.up = coalesce($up, r.up), r.merges = coalesce(r.merges, 0) + 1
MERGE (b)-[:HAS_ROOM]->(r)
