// Every relation edge touching the given objects, either direction ($ids: global object ids;
// $types: the relation whitelist), to check the pairs a merge touched for contradictions.
MATCH (a:Object)-[e]->(b:Object)
WHERE (a.id IN $ids OR b.id IN $ids) AND type(e) IN $types
RETURN a.id AS s, type(e) AS type, b.id AS o, e.score AS score, e.count AS count
