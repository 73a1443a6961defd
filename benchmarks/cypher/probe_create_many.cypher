// The probes the runaway statements collect
UNWIND range(1, $count) AS i
CREATE (:Probe {id: 'p' + toString(i)})
