// Every stored tally (sg3d db check compares them with a recount of the objects, tally_source).
MATCH (t:Tally)
RETURN t.room AS room, t.label AS label, t.colour AS colour, t.n AS n
