// The room's present objects as a re-scan's removal test needs them: id and box. The room's
// structure (floor, walls, surfaces) is not an object that can be taken away.
MATCH (o:Object)
WHERE o.room = $room AND o.removed_at IS NULL AND coalesce(o.layer, 'object') <> 'structure'
RETURN o.id AS id, o.box_centre AS box_centre, o.x AS x, o.y AS y, o.z AS z, o.size AS size,
       o.surface AS surface
ORDER BY o.id
