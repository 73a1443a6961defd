// Centre of each object's 3-D box (null when only the position mean is known), for the pictures.
MATCH (b:Building)-[:HAS_ROOM]->(r:Room)-[:CONTAINS]->(o:Object)
WHERE b.id = $building AND ($room IS NULL OR r.name = $room)
  AND o.removed_at IS NULL
RETURN o.id AS id, o.box_centre AS box_centre
