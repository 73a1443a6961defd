// Every object (any label) of the asked colour (null = any) and rooms (null = all).
MATCH (o:Object)
WHERE ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score
ORDER BY id
LIMIT $limit
