// Every write the store kept
MATCH (p:Probe)
RETURN p.n
