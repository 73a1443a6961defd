// Rows whose colour2 only matches $colour come too: the answer says how many it left out.
// The objects of the asked labels (null = any) and colour in a few rooms, from the rooms (see
// vqa_count_in_rooms for why), with the fields of vqa_provenance: a room-scoped answer counts
// these rows and names its provenance from them, one query instead of three.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour OR o.colour2 = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.colour2 AS colour2, o.volume AS volume, o.size AS size,
       o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.score AS score,
       o.observations AS observations, o.n_frames AS n_frames, o.first_frame AS first_frame,
       o.last_frame AS last_frame, o.updated_at AS updated_at
ORDER BY id
LIMIT $limit
