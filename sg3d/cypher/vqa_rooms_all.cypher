// Every room of a building (null = all buildings), with its up direction.
MATCH (r:Room)
WHERE $building IS NULL OR toLower(r.building) = $building
RETURN r.id AS id, r.name AS name, r.building AS building, r.up AS up
ORDER BY id
