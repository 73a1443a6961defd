// Forget a room's unusable up direction (readers then take the default, +z).
MATCH (r:Room {id: $room})
SET r.up = null
