// The median volume of every stored object of each asked label: the yardstick of "big"/"small"
// (percentileCont = the mean of the two middle values, as statistics.median).
MATCH (o:Object)
WHERE o.label IN $labels
  AND o.volume IS NOT NULL
  AND o.removed_at IS NULL
RETURN o.label AS label, percentileCont(o.volume, 0.5) AS median
