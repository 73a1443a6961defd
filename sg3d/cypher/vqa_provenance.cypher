// What an answer rests on: per object, how sure the store is of it and when it was last seen.
MATCH (o:Object)
WHERE o.id IN $ids
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.room AS room, o.score AS score,
       o.observations AS observations, o.n_frames AS n_frames, o.first_frame AS first_frame,
       o.last_frame AS last_frame, o.updated_at AS updated_at
ORDER BY id
