// Objects with their 3-D boxes, for viewpoint relations computed at query time ($labels and
// $colour null = any, $rooms null = all rooms).
MATCH (o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, o.box_centre AS box_centre, o.x AS x, o.y AS y, o.z AS z
ORDER BY id
