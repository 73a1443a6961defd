"""detect: a stage of the ingest pipeline."""
