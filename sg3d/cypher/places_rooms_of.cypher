// The found room (`sg3d build --rooms auto`) each of some objects is in, with its guessed kind.
MATCH (o:Object)-[:IN_ROOM]->(p:WalkRoom)
WHERE o.id IN $ids
RETURN o.id AS id, p.name AS name, p.kind_guess AS kind_guess, p.kind_evidence AS kind_evidence
ORDER BY id
