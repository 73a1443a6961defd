// The version of the whole store's content as merges, publishes and ingests leave it (the answer
// cache's key): the number of rooms, the sum of their revisions (each merge or publish bumps its
// room's, cypher/room_ensure) and the latest time a room was made. A merge raises the sum, a new
// room the count and the latest birth, a deleted room lowers the count: any of them changes it.
MATCH (r:Room)
RETURN count(r) AS rooms, sum(coalesce(r.revision, 0)) AS revisions, max(r.born) AS born
