// The doorways between the rooms found in a walk: (a)-[:CONNECTED]->(d:Doorway)-[:CONNECTED]->(b),
// with the doorway's middle (world frame) and its clear width in metres.
UNWIND $doorways AS d
MATCH (a:WalkRoom {id: d.a})
MATCH (b:WalkRoom {id: d.b})
CREATE (x:Doorway {id: d.id, walk: $room, x: d.x, y: d.y, z: d.z, width: d.width})
CREATE (a)-[:CONNECTED]->(x)
CREATE (x)-[:CONNECTED]->(b)
