// The room's lease node exists (its own small transaction before a writer takes it); it may
// exist before the room does.
MERGE (l:Lease {room: $room})
