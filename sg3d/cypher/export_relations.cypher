// Relation edges between the exported objects ($types: the relation whitelist).
MATCH (b:Building)-[:HAS_ROOM]->(r:Room)-[:CONTAINS]->(a:Object)-[e]->(o:Object)
WHERE b.id = $building AND ($room IS NULL OR r.name = $room) AND type(e) IN $types
RETURN a.id AS s, type(e) AS type, o.id AS o, e.score AS score, e.count AS count
ORDER BY s, type, o
