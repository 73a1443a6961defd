// Benchmark bulk loader: rooms with their objects in one statement (no merge logic; scratch stores
// only). Each object row: {props, thumbnail}; the thumbnail goes to the object's Appearance.
UNWIND $rooms AS r
MERGE (b:Building {id: r.building})
ON CREATE SET b.name = r.building
CREATE (room:Room {id: r.id, name: r.name, building: r.building})
CREATE (b)-[:HAS_ROOM]->(room)
WITH room, r
UNWIND r.objects AS p
CREATE (o:Object)
SET o = p.props
CREATE (room)-[:CONTAINS]->(o)
CREATE (a:Appearance)
SET a.id = p.props.id, a.thumbnail = p.thumbnail
