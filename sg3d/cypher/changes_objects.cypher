// Objects of one room that the given scans added, moved or removed (sg3d changes), removed ones
// included: this is their history.
MATCH (o:Object)
WHERE o.room = $room
  AND (o.first_scan IN $scans OR o.removed_scan IN $scans OR size([s IN coalesce(o.history_scans, []) WHERE s IN $scans]) > 0)
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.room AS room, o.x AS x, o.y AS y, o.z AS z,
       o.first_frame AS first_frame, o.first_scan AS first_scan, o.first_seen AS first_seen,
       o.last_seen AS last_seen, o.removed_at AS removed_at, o.removed_scan AS removed_scan,
       o.empty_frames AS empty_frames, o.history_scans AS history_scans, o.history_at AS history_at,
       o.history_x AS history_x, o.history_y AS history_y, o.history_z AS history_z
ORDER BY id
