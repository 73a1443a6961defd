// A room's frame -> building frame: 16 floats, row-major 4x4.
// (A new placement bumps the room's revision, as a merge does: answers kept by `sg3d serve` read it.)
MATCH (r:Room {id: $room})
SET r.to_building = $transform, r.revision = coalesce(r.revision, 0) + 1
RETURN r.id AS id
