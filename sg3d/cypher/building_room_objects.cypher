// Objects of one room with what alignment and cross-room linking need (room frame positions),
// the histogram from each object's Appearance.
MATCH (o:Object)
WHERE o.room = $room
  AND o.removed_at IS NULL
OPTIONAL MATCH (a:Appearance {id: o.id})
RETURN o.id AS id, o.label AS label, o.labels AS labels, o.x AS x, o.y AS y, o.z AS z,
       o.box_centre AS box_centre, a.hist AS hist
ORDER BY id
