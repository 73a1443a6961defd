// The room's lease given to (or renewed for) one writer until $expires.
MATCH (l:Lease {room: $room})
SET l.token = $token, l.kind = $kind, l.holder = $holder, l.pid = $pid, l.host = $host,
    l.since = $since, l.expires = $expires
