// Matched nodes take the combined attributes computed by the merge.
UNWIND $rows AS row
MATCH (o:Object {id: row.id})
SET o += row.props
