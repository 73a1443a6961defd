// `sg3d rooms unlink A B`: the SAME_AS links between the objects of two rooms, whichever way they
// point (run with building_unlink_adjacent in one transaction); how many were removed.
MATCH (a:Object)-[s:SAME_AS]-(b:Object)
WHERE a.room = $room_a AND b.room = $room_b
DELETE s
RETURN count(s) AS n
