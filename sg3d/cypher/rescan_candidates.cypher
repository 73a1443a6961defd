// Objects of the room whose place this scan saw empty: candidates for a moved object (same
// attributes as merge_candidates; histograms come from merge_candidate_hists).
MATCH (o:Object)
WHERE o.room = $room AND o.id IN $ids AND o.removed_at IS NULL
RETURN o.id AS id, o.x AS x, o.y AS y, o.z AS z, o.var AS var, o.size AS size,
       o.box_centre AS box_centre, o.label AS label, o.labels AS labels, o.scores AS scores, o.n_points AS n_points,
       o.colour AS colour, o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.observations AS observations, o.n_frames AS n_frames, o.scans AS scans,
       o.first_seen AS first_seen, o.first_scan AS first_scan, o.last_scan AS last_scan,
       o.removed_at AS removed_at, o.history_scans AS history_scans, o.history_at AS history_at,
       o.history_x AS history_x, o.history_y AS history_y, o.history_z AS history_z
ORDER BY o.id
