// Number of objects in one room.
MATCH (o:Object)
WHERE o.room = $room
RETURN count(o) AS n
