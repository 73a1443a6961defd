// Rooms to draw (one room, or every room of a building) with their up direction (null when unknown).
MATCH (b:Building)-[:HAS_ROOM]->(r:Room)
WHERE b.id = $building AND ($room IS NULL OR r.name = $room)
RETURN r.name AS room, r.id AS id, r.up AS up
ORDER BY room
