// The first statement of taking or renewing a room's lease: a write to the lease node, so two
// writers taking one lease at once conflict and the store runs the loser again after the winner,
// which then sees the winner's holder. Returns the holder as it stood.
MATCH (l:Lease {room: $room})
SET l.turns = coalesce(l.turns, 0) + 1
RETURN l.token AS token, l.kind AS kind, l.holder AS holder, l.pid AS pid, l.host AS host,
       l.since AS since, l.expires AS expires
