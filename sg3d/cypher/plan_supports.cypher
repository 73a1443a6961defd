// Support edges (which object stands on or lies in which) between objects of one room;
// $types is a whitelist of relation types from the planning rules (ON, IN).
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room AND b.room = $room AND type(e) IN $types
  AND a.removed_at IS NULL
  AND b.removed_at IS NULL
RETURN a.id AS s, type(e) AS type, b.id AS o, e.score AS score
ORDER BY s, score DESC, o
