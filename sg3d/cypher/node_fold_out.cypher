// Folding node $old into node $into (same object): its outgoing REL_TYPE edges move to $into.
// REL_TYPE is replaced by a member of the relation whitelist.
MATCH (k:Object {id: $old})-[e:REL_TYPE]->(x:Object)
WHERE x.id <> $into
MATCH (j:Object {id: $into})
MERGE (j)-[f:REL_TYPE]->(x)
ON CREATE SET f.score = e.score, f.count = e.count, f.first_at = e.first_at
ON MATCH SET f.score = CASE WHEN e.score > f.score THEN e.score ELSE f.score END,
             f.count = f.count + e.count
