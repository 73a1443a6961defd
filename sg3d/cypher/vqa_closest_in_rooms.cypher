// vqa_closest in a few rooms: anchors and candidates both read from the rooms' CONTAINS edges.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(b:Object)
WHERE b.label IN $anchors
  AND b.removed_at IS NULL
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE o.id <> b.id
  AND ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
WITH o, b, sqrt((o.x - b.x) ^ 2 + (o.y - b.y) ^ 2 + (o.z - b.z) ^ 2) AS distance
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, b.id AS anchor_id, b.label AS anchor_label, distance
ORDER BY distance, id
LIMIT 1
