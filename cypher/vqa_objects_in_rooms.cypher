// The objects of the asked labels (null = any) and colour in a few rooms, from the rooms
// (see vqa_count_in_rooms for why).
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score
ORDER BY id
LIMIT $limit
