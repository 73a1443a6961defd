// Constraints and indexes of the scene-graph model. Idempotent: run at every schema upgrade.
// (:Building)-[:HAS_ROOM]->(:Room)-[:CONTAINS]->(:Object)-[:<RELATION>]->(:Object)
// (:Object)-[:INSTANCE_OF]->(:Category)-[:IS_A]->(:Category)
// (:Appearance {id, hist, thumbnail}) holds an Object's colour histogram and thumbnail under the
// Object's id (schema 2): the bulky bytes stay off the Object record that merges and counts read.
// (:Tally {key, kind: 'label|colour', room, label, colour, n}): objects per room, label and colour
// ('' = all), kept by the merge (graphdb/tally.py) so store-wide counts read no Object record.
// (:Scan {id, room, at}): one build or ingest batch; Objects carry first_seen/last_seen,
// first_scan/last_scan, scans, and when a re-scan saw them gone removed_at/removed_scan (kept,
// never deleted) or when they moved history_scans/history_at/history_x|y|z (earlier places).
CREATE CONSTRAINT building_id IF NOT EXISTS FOR (b:Building) REQUIRE b.id IS UNIQUE;
CREATE CONSTRAINT room_id IF NOT EXISTS FOR (r:Room) REQUIRE r.id IS UNIQUE;
CREATE CONSTRAINT object_id IF NOT EXISTS FOR (o:Object) REQUIRE o.id IS UNIQUE;
CREATE CONSTRAINT appearance_id IF NOT EXISTS FOR (a:Appearance) REQUIRE a.id IS UNIQUE;
CREATE CONSTRAINT category_name IF NOT EXISTS FOR (c:Category) REQUIRE c.name IS UNIQUE;
CREATE CONSTRAINT scan_id IF NOT EXISTS FOR (s:Scan) REQUIRE s.id IS UNIQUE;
CREATE CONSTRAINT merge_key IF NOT EXISTS FOR (m:MergeLog) REQUIRE m.key IS UNIQUE;
CREATE INDEX object_room IF NOT EXISTS FOR (o:Object) ON (o.room);
CREATE INDEX object_label IF NOT EXISTS FOR (o:Object) ON (o.label);
CREATE INDEX room_name IF NOT EXISTS FOR (r:Room) ON (r.name);
CREATE INDEX tally_kind IF NOT EXISTS FOR (t:Tally) ON (t.kind);
// Not a unique constraint: two first merges of one new room would both create its tallies and the
// loser's commit would fail on the key (not retried) instead of on the room lock (retried).
CREATE INDEX tally_key IF NOT EXISTS FOR (t:Tally) ON (t.key)
