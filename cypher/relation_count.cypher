// Number of relation edges between objects of one room.
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room
RETURN count(e) AS n
