// A list grown to 1e6 items by concatenation in one row
RETURN size(reduce(l = [], x IN range(1, 1000000) | l + [x])) AS n
