// Objects of one room with what alignment and cross-room linking need (room frame positions).
MATCH (o:Object)
WHERE o.room = $room
RETURN o.id AS id, o.label AS label, o.labels AS labels, o.x AS x, o.y AS y, o.z AS z,
       o.box_centre AS box_centre, o.hist AS hist
ORDER BY id
