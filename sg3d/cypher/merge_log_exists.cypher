// Has the local graph with this key been merged already? (re-runs and --resume skip it)
MATCH (m:MergeLog {key: $key})
RETURN m.key AS key
