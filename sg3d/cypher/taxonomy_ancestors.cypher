// Every category above one, with its distance (1 = the parent).
MATCH p = (c:Category {name: $category})-[:IS_A*1..]->(a:Category)
RETURN a.name AS name, length(p) AS depth
ORDER BY depth
