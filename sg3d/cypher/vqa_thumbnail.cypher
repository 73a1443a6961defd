// The thumbnail (JPEG bytes) of one object: the multimodal answer (from its Appearance).
MATCH (a:Appearance {id: $id})
RETURN a.thumbnail AS thumbnail
