// New nodes of a room, each with its CONTAINS edge.
MATCH (r:Room {id: $room})
UNWIND $rows AS row
CREATE (o:Object)
SET o = row.props
CREATE (r)-[:CONTAINS]->(o)
