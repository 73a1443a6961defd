// Objects of the rooms to export (one room, or every room of a building).
MATCH (b:Building)-[:HAS_ROOM]->(r:Room)-[:CONTAINS]->(o:Object)
WHERE b.id = $building AND ($room IS NULL OR r.name = $room)
RETURN r.name AS room, o {.*} AS o
ORDER BY room, o.id
