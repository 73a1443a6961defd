// child IS_A parent, for each pair; run after taxonomy_clear, so CREATE cannot duplicate.
UNWIND $pairs AS p
MATCH (c:Category {name: p.child})
MATCH (g:Category {name: p.parent})
CREATE (c)-[:IS_A]->(g)
