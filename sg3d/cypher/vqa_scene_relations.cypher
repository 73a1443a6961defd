// The stored relation edges leaving the given objects ($ids), of the whitelisted $types.
MATCH (o:Object)-[e]->(b:Object)
WHERE o.id IN $ids
  AND type(e) IN $types
  AND b.removed_at IS NULL
RETURN o.id AS s, type(e) AS type, b.id AS o, e.score AS score
ORDER BY s, type, o
