// The version of the category taxonomy loaded into this store (kept on the root category).
MATCH (m:Category {name: $root})
RETURN m.taxonomy_version AS version
