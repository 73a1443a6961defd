// Keys of the merges logged under one build (prefix), for --resume.
MATCH (m:MergeLog)
WHERE m.key STARTS WITH $prefix
RETURN m.key AS key
