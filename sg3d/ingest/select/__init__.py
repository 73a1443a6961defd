"""select: a stage of the ingest pipeline."""
