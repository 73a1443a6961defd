"""Scene-graph file formats: conversions of an exported graph (`sg3d.core.stored.StoredGraph`, as
`sg3d.graphdb.export.fetch_graph` reads it) to and from files; nothing here touches the store."""
