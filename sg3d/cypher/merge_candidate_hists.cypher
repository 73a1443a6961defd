// Same-node candidates that passed the position test: their colour histograms (Appearance,
// unique index on id). The thumbnail bytes stay in the store.
MATCH (a:Appearance)
WHERE a.id IN $ids
RETURN a.id AS id, a.hist AS hist
