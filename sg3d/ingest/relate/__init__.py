"""relate: a stage of the ingest pipeline."""
