// Number of objects in the whole store (benchmarks).
MATCH (o:Object)
WHERE o.removed_at IS NULL
RETURN count(o) AS n
