// Every object of one recorded room with the found rooms it is IN_ROOM (exactly one when the places
// layer is written): which room the fridge is in.
MATCH (o:Object)
WHERE o.room = $room AND o.removed_at IS NULL
OPTIONAL MATCH (o)-[:IN_ROOM]->(p:WalkRoom)
RETURN o.id AS id, o.label AS label, collect(p.name) AS rooms
ORDER BY id
