// The unnamed objects ($unnamed: the label of what no detector named) of the object layer in
// the asked rooms ($rooms null = all), each with what it rests on or is in ($support_types: ON,
// IN), that node's label, colour and size and the edge's score: what could be an asked kind that
// has no named object in scope (sg3d/queries/unnamed.py). One row per object and support edge.
MATCH (o:Object)
WHERE o.label = $unnamed
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND o.removed_at IS NULL
  AND (o.layer IS NULL OR o.layer = 'object')
OPTIONAL MATCH (o)-[e]->(s:Object)
WHERE type(e) IN $support_types
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.shape AS shape, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score, o.observations AS observations,
       o.n_frames AS n_frames, o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.updated_at AS updated_at, type(e) AS support_type, s.label AS support_label,
       s.colour AS support_colour, s.size AS support_size, e.score AS support_score
ORDER BY id
LIMIT $limit
