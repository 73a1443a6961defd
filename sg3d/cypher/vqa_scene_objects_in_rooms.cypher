// vqa_scene_objects in a few rooms: from the rooms (unique index) along CONTAINS, so only their
// own objects are read.
// The rows come back as one row holding `rows`, a list of maps (a round trip's records cost the
// driver ~15 us of CPU each, a map in one list ~2 us): `Store.read` hands back the maps.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND o.removed_at IS NULL
WITH o
ORDER BY o.id
LIMIT $limit
RETURN collect({id: o.id, label: o.label, colour: o.colour, colour2: o.colour2, layer: o.layer,
                shape: o.shape, volume: o.volume, size: o.size, room: o.room, x: o.x, y: o.y,
                z: o.z, box_centre: o.box_centre, score: o.score, observations: o.observations,
                n_frames: o.n_frames, first_frame: o.first_frame, last_frame: o.last_frame,
                updated_at: o.updated_at}) AS rows
