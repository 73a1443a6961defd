// Bump the revision of the rooms a write changed, inside that write's transaction (the answer
// cache keys an answer by the revisions of the rooms it read, cypher/room_revisions).
MATCH (r:Room)
WHERE r.id IN $rooms
SET r.revision = coalesce(r.revision, 0) + 1
