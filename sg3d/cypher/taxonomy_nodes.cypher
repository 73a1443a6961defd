// One Category node per class and group name (idempotent).
UNWIND $names AS name
MERGE (:Category {name: name})
