// One lease node per room (sg3d.graphdb.lease): two writers creating it at once meet this
// constraint, and the loser finds the winner's node.
CREATE CONSTRAINT lease_room IF NOT EXISTS FOR (l:Lease) REQUIRE l.room IS UNIQUE
