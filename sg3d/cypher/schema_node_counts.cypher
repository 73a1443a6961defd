// Nodes per label set: the live part of the graph schema an agent reads before its own Cypher.
MATCH (n)
RETURN labels(n) AS labels, count(*) AS n
ORDER BY n DESC
