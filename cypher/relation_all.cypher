// Every relation edge between objects of one room.
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room
RETURN a.id AS s, type(e) AS type, b.id AS o, e.score AS score, e.count AS count
ORDER BY s, type, o
