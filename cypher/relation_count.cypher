// Number of relation edges between objects of one room ($types: the relation whitelist).
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room AND type(e) IN $types
RETURN count(e) AS n
