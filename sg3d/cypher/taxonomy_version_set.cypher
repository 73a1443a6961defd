// Mark the loaded taxonomy version on the root category.
MATCH (m:Category {name: $root})
SET m.taxonomy_version = $version
