// The names and guessed kinds of the rooms found in the walks of a building's recorded rooms (null =
// every building): words a question may call a room by.
MATCH (w:Room)-[:HAS_PART]->(p:WalkRoom)
WHERE $building IS NULL OR toLower(w.building) = $building
RETURN p.name AS name, p.kind_guess AS kind_guess
ORDER BY name
