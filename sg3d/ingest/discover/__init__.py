"""discover: a stage of the ingest pipeline."""
