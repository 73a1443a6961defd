// Links between two rooms from an earlier alignment, whichever way they point: a re-link
// replaces them (a new transform can move which objects coincide).
MATCH (a:Object)-[s:SAME_AS]-(b:Object)
WHERE a.room = $room_a AND b.room = $room_b
DELETE s
