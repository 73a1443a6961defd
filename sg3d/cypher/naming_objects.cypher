// Every object of the given labels in the given rooms, with what each stands on or is in
// ($support_types: ON, IN), for queries/naming.py: names are decided among all objects of a
// label in a room, whatever subset an answer shows. One row per object and support edge.
// The rows come back as one row holding `rows`, a list of maps (a round trip's records cost the
// driver ~15 us of CPU each, a map in one list ~2 us): `Store.read` hands back the maps.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE o.label IN $labels
  AND o.removed_at IS NULL
OPTIONAL MATCH (o)-[e]->(s:Object)
WHERE type(e) IN $support_types
WITH o, e, s
ORDER BY o.id
RETURN collect({id: o.id, label: o.label, colour: o.colour, room: o.room, x: o.x, y: o.y, z: o.z,
                first_frame: o.first_frame, shape: o.shape, size: o.size, support_type: type(e),
                support_label: s.label, support_score: e.score}) AS rows
