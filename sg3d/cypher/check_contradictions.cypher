// Consistency of the stored relations of one room. Per unordered pair (lo = smaller id) each
// edge is named by a tag: its type read from lo, '~' + type when read backwards. $exclusive
// lists the tag pairs "X|Y" that cannot both hold (core.relation_rules.exclusive_tag_pairs),
// $non_canonical the backwards symmetric tags, $viewpoint the types never stored.
MATCH (a:Object)-[e]->(b:Object)
WHERE a.room = $room AND type(e) IN $types
  AND a.removed_at IS NULL
  AND b.removed_at IS NULL
WITH CASE WHEN a.id < b.id THEN a.id ELSE b.id END AS lo,
     CASE WHEN a.id < b.id THEN b.id ELSE a.id END AS hi,
     CASE WHEN a.id < b.id THEN type(e) ELSE '~' + type(e) END AS tag,
     type(e) AS rel
WITH lo, hi, collect(tag) AS tags, collect(rel) AS rels
WITH lo, hi, tags,
     [p IN $exclusive WHERE split(p, '|')[0] IN tags AND split(p, '|')[1] IN tags] AS clashes,
     [t IN tags WHERE t IN $non_canonical] AS backwards,
     [r IN rels WHERE r IN $viewpoint] AS seen_from
RETURN count(*) AS pairs,
       sum(CASE WHEN size(clashes) > 0 THEN 1 ELSE 0 END) AS contradictory_pairs,
       sum(size(backwards)) AS non_canonical_symmetric,
       sum(size(seen_from)) AS viewpoint_edges,
       collect(CASE WHEN size(clashes) > 0 THEN [lo, hi] + clashes END) AS examples
