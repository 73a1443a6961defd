// Number of objects in one room.
MATCH (o:Object)
WHERE o.room = $room
  AND o.removed_at IS NULL
RETURN count(o) AS n
