// New nodes of a room, each with its CONTAINS edge and its Appearance (histogram, thumbnail),
// then the room's tally changes of the whole merge ($tallies, rows of cypher/tally_add.cypher:
// created, relabelled, recoloured and folded objects) in the same statement: one round trip.
// count(*) folds the created rows into one, so the tallies are written once, also when
// $rows is empty.
// Properties are spelt out in CREATE, not SET o = row.props: on ArcadeDB one record write instead
// of a create then a rewrite (measured 1.25-1.4x more upserts/s). The keys are those of
// graphdb.merge._new_props (tests/test_appearance.py checks they match).
MATCH (r:Room {id: $room})
UNWIND $rows AS row
CREATE (o:Object {id: row.props.id, room: row.props.room, label: row.props.label,
                  labels: row.props.labels, scores: row.props.scores, score: row.props.score,
                  x: row.props.x, y: row.props.y, z: row.props.z, var: row.props.var,
                  n_points: row.props.n_points, size: row.props.size, volume: row.props.volume,
                  box_centre: row.props.box_centre, colour: row.props.colour,
                  colour2: row.props.colour2, layer: row.props.layer, shape: row.props.shape,
                  named_by: row.props.named_by,
                  surface: row.props.surface,
                  first_frame: row.props.first_frame, last_frame: row.props.last_frame,
                  observations: row.props.observations, n_frames: row.props.n_frames,
                  updated_at: row.props.updated_at, first_seen: row.props.first_seen,
                  last_seen: row.props.last_seen, first_scan: row.props.first_scan,
                  last_scan: row.props.last_scan, scans: row.props.scans})
CREATE (r)-[:CONTAINS]->(o)
CREATE (a:Appearance {id: row.props.id, hist: row.hist, thumbnail: row.thumbnail})
WITH count(*) AS created
UNWIND $tallies AS t
MERGE (x:Tally {key: t.key})
ON CREATE SET x.room = t.room, x.label = t.label, x.colour = t.colour, x.kind = t.kind, x.n = 0
SET x.n = x.n + t.n
