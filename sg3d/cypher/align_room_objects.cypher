// Objects of one room with what alignment needs as evidence (`sg3d rooms link`): room-frame
// positions, box size, colour name, layer and how the label was found, the histogram from each
// object's Appearance.
MATCH (o:Object)
WHERE o.room = $room
  AND o.removed_at IS NULL
OPTIONAL MATCH (a:Appearance {id: o.id})
RETURN o.id AS id, o.label AS label, o.labels AS labels, o.x AS x, o.y AS y, o.z AS z,
       o.box_centre AS box_centre, o.size AS size, o.colour AS colour, o.layer AS layer,
       o.named_by AS named_by, a.hist AS hist
ORDER BY id
