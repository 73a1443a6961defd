// Objects per label whatever their label, in the asked rooms (null = all), of the asked colour
// (null = any): counting everything is a scan whatever the plan.
MATCH (o:Object)
WHERE ($rooms IS NULL OR o.room IN $rooms)
  AND ($colour IS NULL OR o.colour = $colour)
RETURN o.label AS label, count(o) AS n
