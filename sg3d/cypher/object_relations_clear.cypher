// A moved object's REL_TYPE edges (both directions) go: they described its old place.
// REL_TYPE is replaced by a member of the relation whitelist.
MATCH (o:Object {id: $id})-[e:REL_TYPE]-(:Object)
DELETE e
