// The room itself, with its HAS_ROOM, ADJACENT and SAME_AS edges (sg3d rooms delete).
MATCH (r:Room {id: $room})
DETACH DELETE r
