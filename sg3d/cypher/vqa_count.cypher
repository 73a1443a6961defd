// Objects per label among the asked labels, of the asked colour (null = any), in the asked rooms
// (null = all; a large room list): sums the per-room tallies (graphdb/tally.py), one small record
// per room, label and colour; no Object record is read. One tally_kind index look-up per label
// ('label|colour', '' = every colour): only the tallies of the asked kind are read.
UNWIND $labels AS l
MATCH (t:Tally)
WHERE t.kind = l + '|' + coalesce($colour, '')
  AND ($rooms IS NULL OR t.room IN $rooms)
WITH t.label AS label, sum(t.n) AS n
WHERE n > 0
RETURN label, n
