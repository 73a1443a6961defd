// How many SAME_AS links the store holds: a type count (constant time), so a store without
// linked rooms never pays for the pair search of vqa_same_as.
MATCH ()-[s:SAME_AS]->()
RETURN count(s) AS n
