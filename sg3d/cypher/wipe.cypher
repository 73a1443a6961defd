// Remove everything (tests and `sg3d db reset`).
MATCH (n)
DETACH DELETE n
