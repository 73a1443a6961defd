// Objects per label in a few rooms: starts from the rooms (unique index) and follows CONTAINS,
// so only the rooms' own objects are read (ArcadeDB picks the label index for
// "o.room IN $rooms AND o.label IN $labels" and reads every object of the label).
MATCH (r:Room)
WHERE r.id IN $rooms
MATCH (r)-[:CONTAINS]->(o:Object)
WHERE ($labels IS NULL OR o.label IN $labels)
  AND ($colour IS NULL OR o.colour = $colour)
  AND o.removed_at IS NULL
RETURN o.label AS label, count(o) AS n
