// The up direction of every room (sg3d db check looks for NaN, Infinity and zero length).
MATCH (r:Room)
RETURN r.id AS id, r.up AS up
