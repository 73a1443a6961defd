// Written in the same transaction as the merge it records: both happen or neither.
CREATE (m:MergeLog {key: $key})
SET m.room = $room, m.at = $at, m.frames = $frames, m.created = $created, m.updated = $updated
