// Same-node candidates, first pass: objects of one room inside a spatial window around the
// local graph, with just what the position similarity needs (Gaussian and 3-D box).
MATCH (o:Object)
WHERE o.room = $room
  AND o.x >= $xmin AND o.x <= $xmax
  AND o.y >= $ymin AND o.y <= $ymax
  AND o.z >= $zmin AND o.z <= $zmax
RETURN o.id AS id, o.x AS x, o.y AS y, o.z AS z, o.var AS var, o.size AS size,
       o.box_centre AS box_centre, o.labels AS labels
