// $anchor_colour: null = an anchor of any colour.
// Objects with a REL_TYPE edge to an anchor object (o -REL_TYPE-> anchor), filtered like
// vqa_objects. Starts from the anchors (object_label index), then their few edges.
MATCH (b:Object)
WHERE b.label IN $anchors
  AND ($anchor_colour IS NULL OR b.colour = $anchor_colour)
  AND ($rooms IS NULL OR b.room IN $rooms)
  AND b.removed_at IS NULL
MATCH (o:Object)-[e:REL_TYPE]->(b)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, b.id AS anchor_id, b.label AS anchor_label, e.score AS rel_score
ORDER BY id, anchor_id
LIMIT $limit
