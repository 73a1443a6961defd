// Rooms of one building with their object counts, transforms and adjacent rooms.
MATCH (:Building {id: $building})-[:HAS_ROOM]->(r:Room)
OPTIONAL MATCH (r)-[:CONTAINS]->(o:Object)
WHERE o.removed_at IS NULL
WITH r, count(o) AS objects
OPTIONAL MATCH (r)-[adj:ADJACENT_TO]->(n:Room)
RETURN r.id AS id, r.name AS name, objects, r.to_building AS to_building,
       collect(n.name) AS adjacent
ORDER BY name
