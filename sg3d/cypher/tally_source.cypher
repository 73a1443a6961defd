// Present (not removed) objects per room, label and colour: what the tallies are recounted from (one scan).
MATCH (o:Object)
WHERE o.removed_at IS NULL
RETURN o.room AS room, o.label AS label, o.colour AS colour, count(*) AS n
