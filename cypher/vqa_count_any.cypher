// Objects per label whatever their label, in the asked rooms, of the asked colour (null = any).
MATCH (o:Object)
WHERE ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
RETURN o.label AS label, count(o) AS n
