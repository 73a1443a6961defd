// The stored edges with one end among some objects of a scene (a relation filter's other set: "not
// on the table"), by those objects' ids (the object_id index), the other end in the scope's rooms.
MATCH (a:Object)
WHERE a.id IN $ids
MATCH (a)-[e]-(o:Object)
WHERE type(e) IN $types
  AND o.removed_at IS NULL
  AND o.room IN $rooms
RETURN a.id AS anchor, o.id AS id, type(e) AS type, startNode(e) = a AS outgoing, e.score AS score
