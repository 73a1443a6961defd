// `sg3d rooms unlink A B`: the ADJACENT_TO edges between two rooms, both directions (run with
// building_unlink_same_as in one transaction); how many were removed.
MATCH (a:Room {id: $room_a})-[e:ADJACENT_TO]-(b:Room {id: $room_b})
DELETE e
RETURN count(e) AS n
