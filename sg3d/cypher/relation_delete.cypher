// Deleting edges of one relation type (REL_TYPE: a member of the whitelist
// core.model.RELATION_TYPES): the losers of a contradiction, or backwards symmetric edges.
UNWIND $rows AS row
MATCH (a:Object {id: row.s})-[e:REL_TYPE]->(b:Object {id: row.o})
DELETE e
