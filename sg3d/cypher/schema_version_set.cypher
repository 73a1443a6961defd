MERGE (m:SchemaInfo {id: 'sg3d'})
SET m.version = $version
