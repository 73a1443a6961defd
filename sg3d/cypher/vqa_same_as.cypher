// SAME_AS pairs (one physical object stored in two rooms) whose both ends match the asked labels
// (null = any), colour (null = any) and rooms (null = all): what a count must not count twice.
// Starts from the rooms that have links (ADJACENT_TO is written with the SAME_AS links); the
// WITH keeps the planner from starting at a scan of every Object.
MATCH (ra:Room)-[:ADJACENT_TO]->(:Room)
WITH DISTINCT ra
MATCH (ra)-[:CONTAINS]->(a:Object)
WHERE a.removed_at IS NULL
MATCH (a)-[:SAME_AS]->(b:Object)
WHERE ($labels IS NULL OR (a.label IN $labels AND b.label IN $labels))
  AND ($rooms IS NULL OR (a.room IN $rooms AND b.room IN $rooms))
  AND ($colour IS NULL OR (a.colour = $colour AND b.colour = $colour))
  AND b.removed_at IS NULL
RETURN a.id AS a, b.id AS b, a.label AS a_label, b.label AS b_label
