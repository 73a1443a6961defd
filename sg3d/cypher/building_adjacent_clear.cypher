// Adjacency between two rooms from an earlier alignment, both directions.
MATCH (a:Room {id: $room_a})-[e:ADJACENT_TO]-(b:Room {id: $room_b})
DELETE e
