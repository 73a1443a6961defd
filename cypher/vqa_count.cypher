// Objects per label among the asked labels, in the asked rooms, of the asked colour (null = any).
MATCH (o:Object)
WHERE o.label IN $labels
  AND ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
RETURN o.label AS label, count(o) AS n
