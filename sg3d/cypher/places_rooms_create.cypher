// The rooms found in a walk (`sg3d build --rooms auto`): one WalkRoom node each, a part of the
// recorded room. polygon: the footprint as a flat list x1, y1, z1, x2, ... (world frame, on the
// floor); area and free_area in square metres; kind_guess is a guess with its evidence, never fact;
// unseen_outline: the share of its outline no seen wall closes (what the walk never looked at).
// The recorded room's revision goes up in the same transaction: answers cached by revision
// (`sg3d serve`) are not served over a layer written after them.
MATCH (w:Room {id: $room})
SET w.revision = coalesce(w.revision, 0) + 1
WITH w
UNWIND $rooms AS r
CREATE (p:WalkRoom {id: r.id, name: r.name, walk: $room, building: w.building, polygon: r.polygon,
                    area: r.area, free_area: r.free_area, x: r.x, y: r.y, z: r.z,
                    kind_guess: r.kind_guess, kind_evidence: r.kind_evidence, unseen_outline: r.unseen_outline})
CREATE (w)-[:HAS_PART]->(p)
