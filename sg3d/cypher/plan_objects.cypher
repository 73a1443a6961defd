// The objects of one room that the planner may name, with what naming and typing need.
MATCH (:Room {id: $room})-[:CONTAINS]->(o:Object)
WHERE o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.room AS room, o.x AS x, o.y AS y, o.z AS z,
       o.first_frame AS first_frame
ORDER BY o.x, o.y, o.z, o.id
