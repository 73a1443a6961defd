"""Scene-graph file formats: conversions of an exported graph ({building, room, nodes, edges},
`graphdb.export.fetch_graph`) to and from files; nothing here touches the store."""
