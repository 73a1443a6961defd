// Rooms whose name is one of the given spellings (room_name index), in a building (null = any):
// the fast path before vqa_rooms' case-insensitive scan.
MATCH (r:Room)
WHERE r.name IN $names
  AND ($building IS NULL OR toLower(r.building) = $building)
RETURN r.id AS id, r.name AS name, r.building AS building
ORDER BY id
