// Rooms that have recorded scans (ask "what changed" without a room).
MATCH (s:Scan)
RETURN DISTINCT s.room AS room
ORDER BY room
