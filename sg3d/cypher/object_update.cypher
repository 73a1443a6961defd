// Matched nodes take the combined attributes computed by the merge; their Appearance the
// combined histogram, and the new thumbnail when one comes (null keeps the stored one).
UNWIND $rows AS row
MATCH (o:Object {id: row.id})
SET o += row.props
MERGE (a:Appearance {id: row.id})
SET a.hist = row.hist, a.thumbnail = coalesce(row.thumbnail, a.thumbnail)
