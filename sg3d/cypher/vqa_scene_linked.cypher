// A scene read from its anchors outwards ("what is on the table"): each object of the scope's rooms
// linked to one of the anchors (by the anchors' ids, the object_id index) by a stored relation,
// either way, with that edge; the fields of cypher/vqa_scene_objects_in_rooms.
// The rows come back as one row holding `rows`, a list of maps (a round trip's records cost the
// driver ~15 us of CPU each, a map in one list ~2 us): `Store.read` hands back the maps.
MATCH (a:Object)
WHERE a.id IN $ids
MATCH (a)-[e]-(o:Object)
WHERE type(e) IN $types
  AND o.removed_at IS NULL
  AND o.room IN $rooms
RETURN collect({id: o.id, label: o.label, colour: o.colour, colour2: o.colour2, layer: o.layer,
                shape: o.shape, volume: o.volume, size: o.size, room: o.room, x: o.x, y: o.y,
                z: o.z, box_centre: o.box_centre, score: o.score, observations: o.observations,
                n_frames: o.n_frames, first_frame: o.first_frame, last_frame: o.last_frame,
                updated_at: o.updated_at, anchor: a.id, type: type(e), outgoing: startNode(e) = a,
                edge_score: e.score}) AS rows
