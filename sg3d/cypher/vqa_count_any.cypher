// Objects per label whatever their label, in the asked rooms (null = all), of the asked colour
// (null = any): sums the per-room tallies (graphdb/tally.py); a scan of the tallies, not of the
// objects.
MATCH (t:Tally)
WHERE t.colour = coalesce($colour, '')
  AND ($rooms IS NULL OR t.room IN $rooms)
WITH t.label AS label, sum(t.n) AS n
WHERE n > 0
RETURN label, n
