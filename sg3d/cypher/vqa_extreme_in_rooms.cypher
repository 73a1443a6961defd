// The extreme-volume object in a few rooms, restricted to the rooms before ordering:
// $sign 1 = biggest, -1 = smallest.
// With the provenance fields and the winner's thumbnail (its Appearance, by the unique index):
// the "show me" answer in one query.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.volume IS NOT NULL
  AND o.removed_at IS NULL
WITH o
ORDER BY o.volume * $sign DESC, o.id
LIMIT 1
OPTIONAL MATCH (a:Appearance {id: o.id})
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score,
       o.observations AS observations, o.n_frames AS n_frames, o.first_frame AS first_frame,
       o.last_frame AS last_frame, o.updated_at AS updated_at, a.thumbnail AS thumbnail
