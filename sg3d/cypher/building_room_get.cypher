// One room by id: its building and its room-to-building transform (null until set).
MATCH (r:Room {id: $room})
RETURN r.id AS id, r.name AS name, r.building AS building, r.to_building AS to_building
