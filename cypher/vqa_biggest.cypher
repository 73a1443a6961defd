// The object of largest volume among the asked labels, rooms and colour.
MATCH (o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.volume IS NOT NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z
ORDER BY o.volume DESC, id
LIMIT 1
