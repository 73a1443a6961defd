// Before a live publish writes the room's relations again: the room's REL_TYPE edges between
// its own objects go (REL_TYPE is replaced by a member of the relation whitelist).
MATCH (a:Object)-[e:REL_TYPE]->(b:Object)
WHERE a.room = $room AND b.room = $room
DELETE e
