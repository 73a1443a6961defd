// Every object of the asked rooms (null = all) with what the compositional reading filters on:
// label, layer, colours, shape, box and provenance; $labels null = any label. Relations, the
// negation and distances are then computed over these rows (ArcadeDB gives wrong results for
// EXISTS{}/COUNT{} subqueries, so "not ..." is not left to a subquery).
MATCH (o:Object)
WHERE ($rooms IS NULL OR o.room IN $rooms)
  AND ($labels IS NULL OR o.label IN $labels)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.colour2 AS colour2, o.layer AS layer,
       o.shape AS shape, o.volume AS volume, o.size AS size, o.room AS room, o.x AS x, o.y AS y,
       o.z AS z, o.box_centre AS box_centre, o.score AS score, o.observations AS observations,
       o.n_frames AS n_frames, o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.updated_at AS updated_at
ORDER BY id
LIMIT $limit
