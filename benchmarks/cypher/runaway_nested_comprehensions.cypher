// 1e9 list items built in one row (refused by the statement guard: literal range bounds)
RETURN size([a IN range(1, 1000) | [b IN range(1, 1000) | [c IN range(1, 1000) | a + b + c]]]) AS n
