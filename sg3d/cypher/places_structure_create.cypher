// The structure of each room found in a walk: (p:WalkRoom)-[:HAS_STRUCTURE]->(o:Object) for every
// floor and wall that bounds it (a wall between two rooms bounds both, the floor every room over it).
UNWIND $rooms AS r
MATCH (p:WalkRoom {id: r.id})
UNWIND coalesce(r.structure, []) AS sid
MATCH (o:Object {id: sid})
CREATE (p)-[:HAS_STRUCTURE]->(o)
