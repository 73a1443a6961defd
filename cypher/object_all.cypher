// Every object of one room with its attributes (export, tests).
MATCH (o:Object)
WHERE o.room = $room
RETURN o {.*} AS o
ORDER BY o.id
