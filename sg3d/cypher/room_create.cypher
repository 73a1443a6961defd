// Create the building and room of a local graph if they are new (its own small transaction, before
// the merge): two builds racing to create one room retry this, not their whole merge.
MERGE (b:Building {id: $building})
ON CREATE SET b.name = $building
MERGE (r:Room {id: $room})
ON CREATE SET r.name = $room_name, r.building = $building, r.born = timestamp()
MERGE (b)-[:HAS_ROOM]->(r)
