// vqa_related in a few rooms: from the rooms to their anchors, then the anchors' edges
// (relation edges never leave a room, so o is in the room too).
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(b:Object)
WHERE b.label IN $anchors
  AND ($anchor_colour IS NULL OR b.colour = $anchor_colour)
  AND b.removed_at IS NULL
MATCH (o:Object)-[e:REL_TYPE]->(b)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, b.id AS anchor_id, b.label AS anchor_label, e.score AS rel_score,
       o.score AS score,
       o.observations AS observations, o.n_frames AS n_frames, o.first_frame AS first_frame,
       o.last_frame AS last_frame, o.updated_at AS updated_at
ORDER BY id, anchor_id
LIMIT $limit
