// The median volume of the stored objects of one label, over at most $sample of them: the
// yardstick of "big"/"small" (percentileCont = the mean of the two middle values, as
// statistics.median). Ids are hashes (sg3d/merge/ids.py), so the first $sample in index order are
// as good as a random sample, the same one in every build of the same frames;
// a label with fewer objects gets its exact median.
MATCH (o:Object)
WHERE o.label = $label
  AND o.volume IS NOT NULL
  AND o.removed_at IS NULL
WITH o.volume AS volume
LIMIT $sample
RETURN percentileCont(volume, 0.5) AS median
