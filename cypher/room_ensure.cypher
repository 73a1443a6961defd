// The building and room a local graph belongs to, created on first use.
MERGE (b:Building {id: $building})
ON CREATE SET b.name = $building
MERGE (r:Room {id: $room})
ON CREATE SET r.name = $name, r.building = $building
SET r.up = coalesce($up, r.up)
MERGE (b)-[:HAS_ROOM]->(r)
