// Each object of a walk in exactly one found room: (o:Object)-[:IN_ROOM]->(p:WalkRoom).
UNWIND $pairs AS pair
MATCH (o:Object {id: pair.object})
MATCH (p:WalkRoom {id: pair.room})
CREATE (o)-[:IN_ROOM]->(p)
