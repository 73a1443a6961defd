// One batch of a room's objects, with their Appearance nodes and every edge (sg3d rooms delete).
MATCH (o:Object)
WHERE o.room = $room
WITH o LIMIT $batch
OPTIONAL MATCH (a:Appearance {id: o.id})
DETACH DELETE o, a
RETURN count(*) AS n
