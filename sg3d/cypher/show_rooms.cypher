// Rooms to draw (one room, or every room of a building): up direction and building transform (null when unknown).
MATCH (b:Building)-[:HAS_ROOM]->(r:Room)
WHERE b.id = $building AND ($room IS NULL OR r.name = $room)
RETURN r.name AS room, r.id AS id, r.up AS up, r.to_building AS to_building
ORDER BY room
