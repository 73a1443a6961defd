// One object seen from two rooms: from the reference room's object to the aligned room's.
UNWIND $rows AS row
MATCH (a:Object {id: row.a})
MATCH (b:Object {id: row.b})
MERGE (a)-[s:SAME_AS]->(b)
SET s.distance = row.distance
