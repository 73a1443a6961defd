// Number of relation edges between objects of one room ($types: the relation whitelist).
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room AND type(e) IN $types
  AND a.removed_at IS NULL
  AND b.removed_at IS NULL
RETURN count(e) AS n
