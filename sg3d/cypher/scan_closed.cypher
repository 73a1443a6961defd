// Records that a scan was closed (its removals decided) and how many objects it removed.
MATCH (s:Scan {id: $id})
SET s.closed_at = $at, s.removed = coalesce(s.removed, 0) + $removed
