// One acknowledged write of the fault benchmark
CREATE (p:Probe {n: $n})
RETURN p.n
