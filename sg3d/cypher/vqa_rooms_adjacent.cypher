// Rooms linked to the given rooms by ADJACENT_TO (they share objects seen from both), with
// how many objects they share.
MATCH (a:Room)-[e:ADJACENT_TO]->(b:Room)
WHERE a.id IN $rooms
RETURN a.id AS room, b.id AS id, b.name AS name, b.building AS building, e.shared_objects AS shared
ORDER BY id
