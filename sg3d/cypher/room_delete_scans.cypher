// A room's scans (sg3d rooms delete).
MATCH (s:Scan)
WHERE s.room = $room
DETACH DELETE s
