// Two rooms that share objects, linked both ways (adjacency is symmetric; one edge per
// direction lets either room be the start of a one-hop traversal).
MATCH (a:Room {id: $room_a})
MATCH (b:Room {id: $room_b})
MERGE (a)-[e:ADJACENT_TO]->(b)
SET e.shared_objects = $shared, e.residual_m = $residual
MERGE (b)-[f:ADJACENT_TO]->(a)
SET f.shared_objects = $shared, f.residual_m = $residual
