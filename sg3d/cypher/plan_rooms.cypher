// Every room of the store (planning picks one by name and building, and lists them on a miss).
MATCH (r:Room)
RETURN r.id AS id, r.name AS name, r.building AS building
ORDER BY r.id
