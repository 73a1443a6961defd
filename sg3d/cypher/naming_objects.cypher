// Every object of the given labels in the given rooms, with what each stands on or is in
// ($support_types: ON, IN), for queries/naming.py: names are decided among all objects of a
// label in a room, whatever subset an answer shows. One row per object and support edge.
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE o.label IN $labels
  AND o.removed_at IS NULL
OPTIONAL MATCH (o)-[e]->(s:Object)
WHERE type(e) IN $support_types
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.room AS room, o.x AS x, o.y AS y,
       o.z AS z, o.first_frame AS first_frame, o.shape AS shape, o.size AS size, type(e) AS support_type, s.label AS support_label,
       e.score AS support_score
ORDER BY id
