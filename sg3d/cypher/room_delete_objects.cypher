// One batch of a room's objects, with their Appearance nodes and every edge (sg3d rooms delete;
// every batch and the other room_delete_* statements run in one transaction, app/rooms.py).
MATCH (o:Object)
WHERE o.room = $room
WITH o LIMIT $batch
OPTIONAL MATCH (a:Appearance {id: o.id})
DETACH DELETE o, a
RETURN count(*) AS n
