// Whether a room node exists (to tell "empty room" from "no such room").
MATCH (r:Room)
WHERE r.id = $room
RETURN r.id AS id
