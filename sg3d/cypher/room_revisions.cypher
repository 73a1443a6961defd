// Every room's revision, read in one round trip by the answer cache of `sg3d serve` (its key): each
// write that changes what an answer over a room can read bumps that room's revision in its own
// transaction (cypher/room_ensure, room_bump, room_bump_all, building_set_transform,
// room_up_clear); `born` (when the room was made) tells a room made again after a delete from the
// one before; id, name and building are the room list the question reader reads names from.
MATCH (r:Room)
RETURN r.id AS id, r.name AS name, r.building AS building, r.born AS born,
       coalesce(r.revision, 0) AS revision
ORDER BY id
