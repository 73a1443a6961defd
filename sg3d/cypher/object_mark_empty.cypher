// Frames of scan $scan that saw the place of a stored object empty (ingest/rescan.py): added to
// the object's evidence of that scan (evidence of an older scan is replaced).
UNWIND $rows AS row
MATCH (o:Object {id: row.id})
WITH o, row, CASE WHEN o.empty_scan = $scan THEN o.empty_frames ELSE [] END AS before
SET o.empty_frames = before + [f IN row.frames WHERE NOT f IN before], o.empty_scan = $scan
