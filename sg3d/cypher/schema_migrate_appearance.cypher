// Schema 1 -> 2, one batch: move the histogram and thumbnail of up to $batch Objects that still
// carry them onto their (:Appearance) node. Run until it returns 0 (graphdb/store.py).
MATCH (o:Object)
WHERE o.hist IS NOT NULL OR o.thumbnail IS NOT NULL
WITH o
LIMIT $batch
MERGE (a:Appearance {id: o.id})
SET a.hist = o.hist, a.thumbnail = o.thumbnail
REMOVE o.hist, o.thumbnail
RETURN count(o) AS n
