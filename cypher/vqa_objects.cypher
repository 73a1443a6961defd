// The objects of the asked labels (null = any), rooms and colour: what answers and lists show.
MATCH (o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score
ORDER BY id
LIMIT $limit
