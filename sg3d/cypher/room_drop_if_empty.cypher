// A room that a failed ingest created and nothing filled (no merge committed, no object): removed
// with its edges, so a failed `POST /ingest` leaves nothing behind. A room any merge reached stays.
MATCH (r:Room {id: $room})
WHERE coalesce(r.merges, 0) = 0
OPTIONAL MATCH (o:Object)
WHERE o.room = $room
WITH r, count(o) AS objects
WHERE objects = 0
DETACH DELETE r
RETURN count(*) AS n
