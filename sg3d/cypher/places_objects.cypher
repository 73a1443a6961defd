// The objects of one recorded room that the places layer puts in a found room (their positions;
// the boxes' sizes say which found rooms a floor or wall bounds).
MATCH (o:Object)
WHERE o.room = $room AND o.removed_at IS NULL
RETURN o.id AS id, o.label AS label, o.layer AS layer, o.x AS x, o.y AS y, o.z AS z, o.size AS size
ORDER BY id
