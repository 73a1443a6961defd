// The up direction of rooms (world frame of their sequence), for viewpoint relations.
MATCH (r:Room)
WHERE r.id IN $rooms
RETURN r.id AS id, r.up AS up
