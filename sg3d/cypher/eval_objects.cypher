// Objects of one room with what evaluation needs (no thumbnails or histograms).
MATCH (o:Object)
WHERE o.room = $room
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.x AS x, o.y AS y, o.z AS z, o.size AS size, o.colour AS colour,
       o.layer AS layer, o.box_centre AS box_centre
ORDER BY id
