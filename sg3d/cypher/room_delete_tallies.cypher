// A room's counting tallies (sg3d rooms delete).
MATCH (t:Tally)
WHERE t.room = $room
DETACH DELETE t
