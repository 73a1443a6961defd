"""The shared model every layer speaks: the plain data of local scene graphs (`model`), the
relation vocabulary and its rules (`relation_rules`), and label embeddings (`embedding`)."""
