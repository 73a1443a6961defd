// The rooms found in the walks of one building's recorded rooms: ids and names (what a rename
// looks its room up among and checks the new name against).
MATCH (w:Room)-[:HAS_PART]->(p:WalkRoom)
WHERE toLower(w.building) = $building
RETURN p.id AS id, p.name AS name, w.id AS walk, w.name AS walk_name
ORDER BY walk, id
