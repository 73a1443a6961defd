// The rooms found in one recorded room's walk and their doorways (nodes carrying walk = the
// recorded room's id), with their CONNECTED and IN_ROOM edges: removed before the layer is written again.
MATCH (n)
WHERE (n:WalkRoom OR n:Doorway) AND n.walk = $room
DETACH DELETE n
