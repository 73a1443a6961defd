// The objects a live map published last in a room (sg3d map): what the next publish keeps
// (same id), changes or removes. Small records only; no histogram or thumbnail.
MATCH (o:Object)
WHERE o.room = $room
RETURN o.id AS id, o.label AS label, o.layer AS layer, o.x AS x, o.y AS y, o.z AS z,
       o.first_seen AS first_seen
