// A build's merge logs whose objects are gone from the room: the build merges its chunks again.
MATCH (m:MergeLog)
WHERE m.key STARTS WITH $prefix
DELETE m
