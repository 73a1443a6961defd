// The rooms found in the walks of a building's recorded rooms (null = every building): their names,
// guessed kinds with evidence, middles, what each holds (IN_ROOM) and the rooms each reaches
// through a doorway (CONNECTED), for the questions over the places layer.
MATCH (w:Room)-[:HAS_PART]->(p:WalkRoom)
WHERE $building IS NULL OR toLower(w.building) = $building
OPTIONAL MATCH (o:Object)-[:IN_ROOM]->(p)
WITH w, p, collect({id: o.id, label: o.label, layer: o.layer, room: o.room, removed: o.removed_at}) AS held
OPTIONAL MATCH (p)-[:CONNECTED]-(d:Doorway)-[:CONNECTED]-(q:WalkRoom)
WITH w, p, held, collect({doorway: d.id, room: q.id, width: d.width, x: d.x, y: d.y, z: d.z}) AS doors
RETURN p.id AS id, p.name AS name, w.id AS walk, w.name AS walk_name, p.kind_guess AS kind_guess,
       p.kind_evidence AS kind_evidence, p.area AS area, p.x AS x, p.y AS y, p.z AS z,
       [o IN held WHERE o.id IS NOT NULL AND o.removed IS NULL] AS objects,
       [d IN doors WHERE d.doorway IS NOT NULL] AS doorways
ORDER BY walk, id
