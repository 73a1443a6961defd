// The same with the bound in a variable, which the statement guard cannot read
WITH 1000 AS n
RETURN size([a IN range(1, n) | [b IN range(1, n) | [c IN range(1, n) | a + b + c]]]) AS n
