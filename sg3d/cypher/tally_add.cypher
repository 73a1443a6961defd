// Per-room tallies (graphdb/tally.py): add row.n (negative: remove) to the objects counted under
// room, label and colour ('' = every colour). Run inside the merge transaction that changes them.
UNWIND $rows AS row
MERGE (t:Tally {key: row.key})
ON CREATE SET t.room = row.room, t.label = row.label, t.colour = row.colour, t.kind = row.kind, t.n = 0
SET t.n = t.n + row.n
