// Same-node candidates, second pass: the attributes of the ones close enough to matter.
// The thumbnail bytes stay in the store.
MATCH (o:Object)
WHERE o.id IN $ids
RETURN o.id AS id, o.labels AS labels, o.scores AS scores, o.hist AS hist, o.n_points AS n_points,
       o.size AS size, o.colour AS colour, o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.observations AS observations, o.n_frames AS n_frames
