// One relation type per run: REL_TYPE is replaced by a member of the whitelist
// core.model.RELATION_TYPES (Cypher takes no relation type as a parameter).
UNWIND $rows AS row
MATCH (a:Object {id: row.s})
MATCH (b:Object {id: row.o})
MERGE (a)-[e:REL_TYPE]->(b)
ON CREATE SET e.score = row.score, e.count = 1, e.first_at = row.at
ON MATCH SET e.score = CASE WHEN row.score > e.score THEN row.score ELSE e.score END,
             e.count = e.count + 1
