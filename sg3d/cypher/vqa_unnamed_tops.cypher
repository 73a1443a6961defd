// The unnamed objects ($unnamed: the label of what no detector named) of the object layer in the
// asked rooms ($rooms null = all) that something stands ON, with how many things: the tops that
// could be a desk or a table no detector named, when "what is on the desk?" finds no desk
// (sg3d/queries/unnamed.py).
MATCH (o:Object)-[:ON]->(t:Object)
WHERE t.label = $unnamed
  AND ($rooms IS NULL OR t.room IN $rooms)
  AND t.removed_at IS NULL
  AND o.removed_at IS NULL
  AND (t.layer IS NULL OR t.layer = 'object')
RETURN t.id AS id, t.label AS label, t.colour AS colour, t.shape AS shape, t.size AS size, t.room AS room,
       t.x AS x, t.y AS y, t.z AS z, count(o) AS things
ORDER BY id
LIMIT $limit
