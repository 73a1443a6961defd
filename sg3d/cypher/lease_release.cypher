// A writer gives its lease back: the lease node goes, if it is still this writer's.
MATCH (l:Lease {room: $room})
WHERE l.token = $token
DETACH DELETE l
RETURN count(*) AS n
