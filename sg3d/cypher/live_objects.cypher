// The objects of a room a live map publishes into (sg3d map): those a map created (first_scan
// 'map:...') are what the next publish keeps (same id), changes or removes; the others (a build's,
// an ingest's) it leaves as they are and only counts in the room's tallies. Small records only.
MATCH (o:Object)
WHERE o.room = $room
RETURN o.id AS id, o.label AS label, o.layer AS layer, o.x AS x, o.y AS y, o.z AS z,
       o.first_seen AS first_seen, o.first_scan AS first_scan, o.colour AS colour,
       o.removed_at IS NOT NULL AS removed
