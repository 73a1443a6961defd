// Edges per relationship type: the live part of the graph schema.
MATCH ()-[e]->()
RETURN type(e) AS type, count(*) AS n
ORDER BY n DESC
