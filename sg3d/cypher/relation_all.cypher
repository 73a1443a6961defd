// Every relation edge between objects of one room ($types: the relation whitelist,
// so links such as SAME_AS between rooms are not counted as relations).
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room AND type(e) IN $types
  AND a.removed_at IS NULL
  AND b.removed_at IS NULL
RETURN a.id AS s, type(e) AS type, b.id AS o, e.score AS score, e.count AS count
ORDER BY s, type, o
