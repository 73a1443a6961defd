// The scans of one room, oldest first (sg3d changes).
MATCH (s:Scan)
WHERE s.room = $room
RETURN s.id AS id, s.at AS at, s.kind AS kind, s.closed_at AS closed_at, s.removed AS removed
ORDER BY at, id
