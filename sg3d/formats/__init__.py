"""Scene-graph file formats: conversions of an exported graph ({building, room, nodes, edges},
`sg3d.graphdb.export.fetch_graph`) to and from files; nothing here touches the store."""
