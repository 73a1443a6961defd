// Every object of one room with its attributes, histogram and thumbnail (export, tests).
MATCH (o:Object)
WHERE o.room = $room
OPTIONAL MATCH (a:Appearance {id: o.id})
RETURN o {.*, hist: a.hist, thumbnail: a.thumbnail} AS o
ORDER BY o.id
