"""objects: a stage of the ingest pipeline."""
