// Forget a room's unusable up direction (readers then take the default, +z).
// (It bumps the room's revision, as a merge does: answers kept by `sg3d serve` read it.)
MATCH (r:Room {id: $room})
SET r.up = null, r.revision = coalesce(r.revision, 0) + 1
