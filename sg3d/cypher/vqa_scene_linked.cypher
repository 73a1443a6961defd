// A scene read from its anchors outwards ("what is on the table"): each object of the scope's rooms
// linked to one of the anchors (by the anchors' ids, the object_id index) by a stored relation,
// either way, with that edge; the fields of cypher/vqa_scene_objects_in_rooms.
MATCH (a:Object)
WHERE a.id IN $ids
MATCH (a)-[e]-(o:Object)
WHERE type(e) IN $types
  AND o.removed_at IS NULL
  AND o.room IN $rooms
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.colour2 AS colour2, o.layer AS layer,
       o.shape AS shape, o.volume AS volume, o.size AS size, o.room AS room, o.x AS x, o.y AS y,
       o.z AS z, o.box_centre AS box_centre, o.score AS score, o.observations AS observations,
       o.n_frames AS n_frames, o.first_frame AS first_frame, o.last_frame AS last_frame,
       o.updated_at AS updated_at, a.id AS anchor, type(e) AS type, startNode(e) = a AS outgoing,
       e.score AS edge_score
