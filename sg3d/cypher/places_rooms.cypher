// The rooms found in one recorded room's walk, with their objects, their structure (the floors and
// walls that bound each) and the rooms they connect to through doorways.
MATCH (p:WalkRoom)
WHERE p.walk = $room
OPTIONAL MATCH (o:Object)-[:IN_ROOM]->(p)
WITH p, collect(o.id) AS objects
OPTIONAL MATCH (p)-[:HAS_STRUCTURE]->(s:Object)
WITH p, objects, collect({id: s.id, label: s.label}) AS bounds
OPTIONAL MATCH (p)-[:CONNECTED]-(d:Doorway)-[:CONNECTED]-(q:WalkRoom)
WITH p, objects, bounds, collect({doorway: d.id, room: q.name, width: d.width, x: d.x, y: d.y, z: d.z}) AS doors
RETURN p.id AS id, p.name AS name, p.area AS area, p.free_area AS free_area, p.polygon AS polygon,
       p.x AS x, p.y AS y, p.z AS z, p.kind_guess AS kind_guess, p.kind_evidence AS kind_evidence,
       objects, [s IN bounds WHERE s.id IS NOT NULL] AS structure, [d IN doors WHERE d.doorway IS NOT NULL] AS doorways
ORDER BY id
