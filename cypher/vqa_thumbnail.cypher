// The thumbnail (JPEG bytes) of one object: the multimodal answer.
MATCH (o:Object {id: $id})
RETURN o.thumbnail AS thumbnail
