// Rows whose second colour ($colour matches colour2 only) are read so the answer can say how
// many it left out (a colour word means the main colour).
// The objects of the asked labels, colour (null = any) and rooms (null = all), from the
// object_label index (see vqa_count for why the label test stands alone).
MATCH (o:Object)
WHERE o.label IN $labels
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour OR o.colour2 = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.colour2 AS colour2, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score
ORDER BY id
LIMIT $limit
