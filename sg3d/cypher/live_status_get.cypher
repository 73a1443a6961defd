// A room's live-mapping state (null fields: never mapped live).
MATCH (r:Room {id: $room})
RETURN r.mapping AS mapping, r.mapping_since AS since, r.mapping_frames AS frames,
       r.mapping_updated AS updated, r.mapping_source AS source
