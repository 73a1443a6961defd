// Before a live publish writes the room's relations again: the room's REL_TYPE edges that touch an
// object the map made ($ids) go; edges between objects of a build or an ingest stay (REL_TYPE is
// replaced by a member of the relation whitelist).
MATCH (a:Object)-[e:REL_TYPE]->(b:Object)
WHERE a.room = $room AND b.room = $room AND (a.id IN $ids OR b.id IN $ids)
DELETE e
