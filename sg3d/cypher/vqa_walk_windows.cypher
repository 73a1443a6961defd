// The rooms found in the walks of a building's recorded rooms (null = every building), each with
// the windows IN it (structure nodes labelled window: middle, size) and the share of its outline
// no seen wall closes, for "which rooms have (no) window".
MATCH (w:Room)-[:HAS_PART]->(p:WalkRoom)
WHERE $building IS NULL OR toLower(w.building) = $building
OPTIONAL MATCH (o:Object)-[:IN_ROOM]->(p)
WHERE o.label = 'window' AND o.removed_at IS NULL
WITH w, p, collect({id: o.id, x: o.x, y: o.y, z: o.z, size: o.size}) AS held
RETURN p.id AS id, p.name AS name, w.id AS walk, p.kind_guess AS kind_guess, p.kind_evidence AS kind_evidence,
       coalesce(p.unseen_outline, 0.0) AS unseen_outline,
       [o IN held WHERE o.id IS NOT NULL] AS windows
ORDER BY walk, id
