// A category and every category below it (a graph search over IS_A, paper Sec. VI-A).
MATCH (d:Category)-[:IS_A*0..]->(c:Category {name: $category})
RETURN DISTINCT d.name AS name
