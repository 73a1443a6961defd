// A room found in a walk gets the name a user gives it (`sg3d rooms rename`); the recorded room's
// revision goes up in the same transaction, so no answer cached over the old name is served.
MATCH (w:Room {id: $room})-[:HAS_PART]->(p:WalkRoom {id: $id})
SET p.name = $name, w.revision = coalesce(w.revision, 0) + 1
RETURN p.id AS id, p.name AS name
