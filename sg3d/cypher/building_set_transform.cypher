// A room's frame -> building frame: 16 floats, row-major 4x4.
MATCH (r:Room {id: $room})
SET r.to_building = $transform
RETURN r.id AS id
