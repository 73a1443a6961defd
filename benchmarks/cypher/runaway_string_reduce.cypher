// A string grown to 10 MB by concatenation in one row
RETURN size(reduce(s = '', x IN range(1, 1000000) | s + 'xxxxxxxxxx')) AS n
