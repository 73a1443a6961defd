// Objects per room, label and colour: what the tallies are recounted from (one scan).
MATCH (o:Object)
RETURN o.room AS room, o.label AS label, o.colour AS colour, count(*) AS n
