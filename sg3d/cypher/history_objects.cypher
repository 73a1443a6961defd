// Objects of the given labels that moved or were removed, with their earlier places (ask "where
// was the cup before"); $room and $building (names) narrow them, null = everywhere.
MATCH (b:Building)-[:HAS_ROOM]->(r:Room)-[:CONTAINS]->(o:Object)
WHERE o.label IN $labels
  AND ($building IS NULL OR b.id = $building)
  AND ($room IS NULL OR r.name = $room)
  AND (o.history_scans IS NOT NULL OR o.removed_at IS NOT NULL)
RETURN o.id AS id, o.label AS label, o.colour AS colour, o.room AS room, o.x AS x, o.y AS y, o.z AS z,
       o.first_frame AS first_frame, o.removed_at AS removed_at, o.removed_scan AS removed_scan,
       o.history_scans AS history_scans, o.history_x AS history_x, o.history_y AS history_y,
       o.history_z AS history_z
ORDER BY id
