// Volumes of every stored object of the asked labels: the reference for "big"/"small".
MATCH (o:Object)
WHERE o.label IN $labels
RETURN o.label AS label, o.volume AS volume
