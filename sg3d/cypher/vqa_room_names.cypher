// The room list the question reader resolves room and building names against (ids and names only:
// the answer cache keys it by the room list, not by any room's revision).
MATCH (r:Room)
WHERE $building IS NULL OR toLower(r.building) = $building
RETURN r.id AS id, r.name AS name, r.building AS building
ORDER BY id
