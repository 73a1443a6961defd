// Same-node candidates: objects of one room inside a spatial window around the local graph,
// with every attribute the merge reads except the histogram (merge_candidate_hists fetches
// that for the few that pass the position test). The Object record holds no bytes (schema 2).
MATCH (o:Object)
WHERE o.room = $room
  AND o.x >= $xmin AND o.x <= $xmax
  AND o.y >= $ymin AND o.y <= $ymax
  AND o.z >= $zmin AND o.z <= $zmax
RETURN o.id AS id, o.x AS x, o.y AS y, o.z AS z, o.var AS var, o.size AS size,
       o.box_centre AS box_centre, o.label AS label, o.labels AS labels, o.scores AS scores, o.n_points AS n_points,
       o.colour AS colour, o.colour2 AS colour2, o.layer AS layer, o.shape AS shape, o.named_by AS named_by,
       o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.observations AS observations, o.n_frames AS n_frames, o.scans AS scans,
       o.first_seen AS first_seen, o.first_scan AS first_scan, o.removed_at AS removed_at
