// Objects per label among the asked labels, of the asked colour (null = any), in the asked rooms
// (null = all; a large room list): sums the per-room tallies (graphdb/tally.py), one small record
// per room and label, from the tally_label index; no Object record is read.
MATCH (t:Tally)
WHERE t.label IN $labels
  AND t.colour = coalesce($colour, '')
  AND ($rooms IS NULL OR t.room IN $rooms)
WITH t.label AS label, sum(t.n) AS n
WHERE n > 0
RETURN label, n
