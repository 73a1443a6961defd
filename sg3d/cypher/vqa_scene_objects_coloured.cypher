// The scope's objects whose main or second colour is $colour ("what is red": the second colour is
// reported, not counted), with the fields of cypher/vqa_scene_objects_in_rooms.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE (o.colour = $colour OR o.colour2 = $colour)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.colour2 AS colour2, o.layer AS layer,
       o.shape AS shape, o.volume AS volume, o.size AS size, o.room AS room, o.x AS x, o.y AS y,
       o.z AS z, o.box_centre AS box_centre, o.score AS score, o.observations AS observations,
       o.n_frames AS n_frames, o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.updated_at AS updated_at
ORDER BY id
LIMIT $limit
