// New nodes of a room, each with its CONTAINS edge and its Appearance (histogram, thumbnail).
MATCH (r:Room {id: $room})
UNWIND $rows AS row
CREATE (o:Object)
SET o = row.props
CREATE (r)-[:CONTAINS]->(o)
CREATE (a:Appearance)
SET a.id = row.props.id, a.hist = row.hist, a.thumbnail = row.thumbnail
