// Objects per label among the asked labels (null = any) and colour (null = any), whole store
// or a large room list. Starts from the object_label index: no "$x IS NULL OR" on the
// indexed property, else ArcadeDB's planner falls back to a scan of every Object.
MATCH (o:Object)
WHERE o.label IN $labels
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
RETURN o.label AS label, count(o) AS n
