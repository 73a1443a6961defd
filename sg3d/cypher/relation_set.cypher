// Setting the support of edges of one relation type (REL_TYPE: a member of the whitelist),
// creating them when missing: the winner of a contradiction keeps the evidence of its pair.
UNWIND $rows AS row
MATCH (a:Object {id: row.s})
MATCH (b:Object {id: row.o})
MERGE (a)-[e:REL_TYPE]->(b)
ON CREATE SET e.first_at = row.at
SET e.score = row.score, e.count = row.count
