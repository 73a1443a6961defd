// A scan of a room (one `sg3d build` or one `POST /ingest` batch): created by its first merge,
// its time kept from then on (a re-run or --resume of the scan is the same scan).
MERGE (s:Scan {id: $id})
ON CREATE SET s.room = $room, s.at = $at, s.kind = $kind
SET s.merges = coalesce(s.merges, 0) + 1
