// A node folded into another: it and its remaining edges go.
MATCH (k:Object {id: $id})
DETACH DELETE k
