// Nested comprehensions over the ids of the 1000 probes
MATCH (n:Probe)
WITH collect(n.id) AS ids
RETURN size([a IN ids | [b IN ids | [c IN ids | a + b + c]]]) AS n
