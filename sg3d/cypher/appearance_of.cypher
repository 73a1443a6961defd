// Histograms and thumbnails of the given objects (export with --thumbnails / --histograms).
MATCH (a:Appearance)
WHERE a.id IN $ids
RETURN a.id AS id, a.hist AS hist, a.thumbnail AS thumbnail
