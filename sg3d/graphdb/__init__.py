"""The graph store: driver and sessions, embedded server lifecycle, schema, merge, export."""
