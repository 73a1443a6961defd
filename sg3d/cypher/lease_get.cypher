// Who holds a room's lease (a writer's transaction checks it is still its own).
MATCH (l:Lease {room: $room})
RETURN l.token AS token, l.kind AS kind, l.holder AS holder, l.pid AS pid, l.host AS host,
       l.since AS since, l.expires AS expires
