// Number of objects in the whole store (benchmarks).
MATCH (o:Object)
RETURN count(o) AS n
