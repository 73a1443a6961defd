// The numbers of every object a reader uses (sg3d db check looks for NaN and Infinity in them).
MATCH (o:Object)
RETURN o.id AS id, o.room AS room, o.x AS x, o.y AS y, o.z AS z, o.var AS var, o.size AS size,
       o.volume AS volume, o.box_centre AS box_centre, o.score AS score
