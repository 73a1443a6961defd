// A reduce inside a reduce inside a reduce: 8e9 additions in one row
WITH range(1, 2000) AS r
RETURN reduce(s = 0, a IN r | s + reduce(t = 0, b IN r | t + reduce(u = 0, c IN r | u + c))) AS x
