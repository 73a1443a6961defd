// A node folded into another: it, its Appearance and its remaining edges go.
MATCH (k:Object {id: $id})
OPTIONAL MATCH (a:Appearance {id: $id})
DETACH DELETE k, a
