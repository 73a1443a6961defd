// Every tally goes (before a recount from the objects, graphdb/tally.py rebuild_tallies).
MATCH (t:Tally)
DETACH DELETE t
