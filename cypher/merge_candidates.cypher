// Same-node candidates: objects of one room inside a spatial window around the local graph.
// Only the properties the similarity needs; the thumbnail bytes stay in the store.
MATCH (o:Object)
WHERE o.room = $room
  AND o.x >= $xmin AND o.x <= $xmax
  AND o.y >= $ymin AND o.y <= $ymax
  AND o.z >= $zmin AND o.z <= $zmax
RETURN o.id AS id, o.labels AS labels, o.scores AS scores, o.x AS x, o.y AS y, o.z AS z,
       o.var AS var, o.n_points AS n_points, o.hist AS hist, o.size AS size, o.colour AS colour,
       o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.observations AS observations, o.n_frames AS n_frames
