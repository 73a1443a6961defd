// The schema version applied to this store, if any.
MATCH (m:SchemaInfo {id: 'sg3d'})
RETURN m.version AS version
