// The unnamed objects ($unnamed: the label of what no detector named) of the object layer in
// the asked rooms ($rooms null = all), each with what it rests on or is in ($support_types: ON,
// IN), that node's label, colour and size and the edge's score: what could be an asked kind that
// has no named object in scope (sg3d/queries/unnamed.py). One row per object and support edge.
// The rows come back as one row holding `rows`, a list of maps (a round trip's records cost the
// driver ~15 us of CPU each, a map in one list ~2 us): `Store.read` hands back the maps.
MATCH (o:Object)
WHERE o.label = $unnamed
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND o.removed_at IS NULL
  AND (o.layer IS NULL OR o.layer = 'object')
OPTIONAL MATCH (o)-[e]->(s:Object)
WHERE type(e) IN $support_types
WITH o, e, s
ORDER BY o.id
LIMIT $limit
RETURN collect({id: o.id, label: o.label, colour: o.colour, shape: o.shape, size: o.size,
                room: o.room, x: o.x, y: o.y, z: o.z, score: o.score, observations: o.observations,
                n_frames: o.n_frames, first_frame: o.first_frame, last_frame: o.last_frame,
                updated_at: o.updated_at, support_type: type(e), support_label: s.label,
                support_colour: s.colour, support_size: s.size, support_score: e.score}) AS rows
