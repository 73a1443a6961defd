// Where objects are: their relation edges to other objects ($ids: the objects asked about;
// $types: the whitelisted spatial relation types). $incoming false = o -rel-> b (o is ON b),
// true = b -rel-> o (only asked for symmetric types: b is NEXT_TO o means o is next to b).
// The direction is tested on startNode(e): ArcadeDB ignores a pattern predicate's arrow on a bound edge.
MATCH (o:Object)
WHERE o.id IN $ids
MATCH (o)-[e]-(b:Object)
WHERE type(e) IN $types
  AND (($incoming AND startNode(e) = b) OR (NOT $incoming AND startNode(e) = o))
RETURN o.id AS id, type(e) AS rel, b.id AS other_id, b.label AS other_label, b.colour AS other_colour,
       e.score AS rel_score
ORDER BY id, rel, other_id
