// Benchmark bulk loader: ON edges between objects given by id.
UNWIND $pairs AS p
MATCH (a:Object {id: p.s})
MATCH (b:Object {id: p.o})
CREATE (a)-[:ON {score: p.score, count: 1}]->(b)
