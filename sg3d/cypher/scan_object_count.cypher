// How many of a room's objects one scan (a build) saw.
MATCH (o:Object)
WHERE o.room = $room AND $scan IN o.scans
RETURN count(o) AS n
