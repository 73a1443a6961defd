// A building left without rooms by room_drop_if_empty (same transaction): removed too.
MATCH (b:Building {id: $building})
OPTIONAL MATCH (b)-[:HAS_ROOM]->(r:Room)
WITH b, count(r) AS rooms
WHERE rooms = 0
DETACH DELETE b
RETURN count(*) AS n
