// A room's merge logs, so the same observations may be merged again (sg3d rooms delete).
MATCH (m:MergeLog)
WHERE m.room = $room
DETACH DELETE m
