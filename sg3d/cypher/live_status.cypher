// What `GET /rooms/{b}/{r}` and `sg3d rooms` say of a room a live map is building: mapping
// ('live' while frames arrive, 'done' once the source ended), since when, how many frames so far.
MATCH (r:Room {id: $room})
SET r.mapping = $state, r.mapping_since = $since, r.mapping_frames = $frames,
    r.mapping_updated = $updated, r.mapping_source = $source
