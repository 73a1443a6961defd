// The merges logged under one build (prefix) and the objects each created: what a re-run skips,
// and whether those objects are still there.
MATCH (m:MergeLog)
WHERE m.key STARTS WITH $prefix
RETURN m.key AS key, m.created AS created
