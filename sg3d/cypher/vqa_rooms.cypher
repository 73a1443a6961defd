// Rooms in the asked scope (names compared in lower case; null = any).
MATCH (r:Room)
WHERE ($room IS NULL OR toLower(r.name) = $room)
  AND ($building IS NULL OR toLower(r.building) = $building)
RETURN r.id AS id, r.name AS name, r.building AS building
ORDER BY id
