// The scan's last merge closes it: objects of the room this scan saw the place of empty in at
// least $min_frames frames, and did not re-observe, are marked removed (never deleted). Returns
// them, so the merge takes them out of the room's tallies in the same transaction.
MATCH (o:Object)
WHERE o.room = $room AND o.empty_scan = $scan AND o.removed_at IS NULL
  AND size(o.empty_frames) >= $min_frames
  AND (o.last_scan IS NULL OR o.last_scan <> $scan)
SET o.removed_at = $at, o.removed_scan = $scan
RETURN o.id AS id, o.label AS label, o.colour AS colour
