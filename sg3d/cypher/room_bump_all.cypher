// Bump every room's revision, inside the transaction of a write whose reach is the whole store (a
// tally recount, a taxonomy load, a user's own writing statement): every kept answer is retired.
MATCH (r:Room)
SET r.revision = coalesce(r.revision, 0) + 1
