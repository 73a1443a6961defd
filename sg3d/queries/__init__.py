"""Reading the graph: questions -> Cypher templates -> answers; graph -> PDDL -> plans."""
