// `sg3d db check`: records missing a property sg3d always writes (an Object's id, room and label,
// a Room's id, a Tally's room and label). None is possible through sg3d: a damaged dictionary of
// property names (the store's own check does not see it) reads as exactly that.
OPTIONAL MATCH (o:Object)
WITH count(o) AS objects,
     sum(CASE WHEN o IS NOT NULL AND (o.id IS NULL OR o.room IS NULL OR o.label IS NULL) THEN 1 ELSE 0 END) AS objects_missing
OPTIONAL MATCH (r:Room)
WITH objects, objects_missing, count(r) AS rooms,
     sum(CASE WHEN r IS NOT NULL AND r.id IS NULL THEN 1 ELSE 0 END) AS rooms_missing
OPTIONAL MATCH (t:Tally)
RETURN objects, coalesce(objects_missing, 0) AS objects_missing, rooms, coalesce(rooms_missing, 0) AS rooms_missing,
       count(t) AS tallies,
       coalesce(sum(CASE WHEN t IS NOT NULL AND (t.room IS NULL OR t.label IS NULL) THEN 1 ELSE 0 END), 0) AS tallies_missing
