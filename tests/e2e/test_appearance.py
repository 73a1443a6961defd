"""Schema 2: an Object's histogram and thumbnail live on its (:Appearance) node, off the record
that merges and counts read; stores of schema 1 are migrated by `Store.ensure_schema`."""
from __future__ import annotations

import numpy as np

from sg3d.core.model import ScanInfo
from sg3d.graphdb import store as store_module
from sg3d.graphdb.export import fetch_graph
from sg3d.graphdb.merge import merge_local_graph
from sg3d.merge.plan import _new_props
from sg3d.graphdb.values import room_id
from sg3d.merge.histograms import pack_hist, unpack_hist
from sg3d.queries.vqa import answer
from tests.factories import graph, hist_of, obj

ROOM = room_id("home", "kitchen")
JPEG = b"\xff\xd8thumb"


def node_counts(store) -> dict[str, int]:
    return {tuple(r["labels"])[0]: r["n"] for r in store.read("schema_node_counts") if r["labels"]}


def raw_objects(store) -> list[dict]:
    """The Object records themselves, as a query of the store reads them."""
    keys, rows = store.run_raw("MATCH (o:Object) RETURN o {.*} AS o ORDER BY o.id")
    return [r[0] for r in rows]


def test_merged_objects_carry_no_bytes_and_their_appearance_does(store):
    h = hist_of({7: 60, 100: 40})
    merge_local_graph(store, graph([obj("a", "cup", (0.0, 0.0, 1.0), hist=h, thumbnail=JPEG),
                                    obj("b", "bowl", (1.0, 0.0, 1.0))]))
    records = raw_objects(store)
    assert len(records) == 2
    # object_create spells the properties out: every one the merge computes is stored, no bytes
    # (a null property, such as the shape of a named object, is not stored)
    props = _new_props(obj("z", "cup", (0, 0, 0)), "o-z", ROOM, 0.0, ScanInfo("s", 0.0))
    own = {k for k, v in props.items() if v is not None} - {"hist", "thumbnail"}
    assert {"layer"} <= own
    assert all(set(o) == own for o in records)
    assert node_counts(store).get("Appearance") == 2
    full = {o["label"]: o for o in (r["o"] for r in store.read("object_all", room=ROOM))}
    assert np.allclose(unpack_hist(full["cup"]["hist"]), h)
    assert bytes(full["cup"]["thumbnail"]) == JPEG


def test_show_me_and_export_read_the_appearance(store):
    merge_local_graph(store, graph([obj("s", "bowl", (0.0, 0.0, 1.0), size=(0.1, 0.1, 0.1)),
                                    obj("b", "bowl", (1.0, 0.0, 1.0), size=(0.4, 0.4, 0.2), thumbnail=JPEG)]))
    a = answer(store, "show me the biggest bowl")
    assert a.ok and a.thumbnail == JPEG
    g = fetch_graph(store, "home", "kitchen", thumbnails=True, histograms=True)
    assert len(g.nodes) == 2 and all(len(n.hist or ()) == 512 for n in g.nodes)
    assert sorted(n.thumbnail_jpeg_base64 or "" for n in g.nodes) == sorted(["/9hqcGVn", "/9h0aHVtYg=="])
    plain = fetch_graph(store, "home", "kitchen").as_json()
    assert all("hist" not in n and "thumbnail_jpeg_base64" not in n for n in plain["nodes"])


def test_a_new_best_view_replaces_the_thumbnail_and_a_weaker_one_keeps_it(store):
    merge_local_graph(store, graph([obj("a", "cup", (0.0, 0.0, 1.0), scores=[0.6], thumbnail=b"\xff\xd8first")]))
    merge_local_graph(store, graph([obj("a", "cup", (0.01, 0.0, 1.0), scores=[0.5], thumbnail=b"\xff\xd8weak")]))
    [o] = [r["o"] for r in store.read("object_all", room=ROOM)]
    assert bytes(o["thumbnail"]) == b"\xff\xd8first" and o["observations"] == 2
    merge_local_graph(store, graph([obj("a", "cup", (0.0, 0.01, 1.0), scores=[0.9], thumbnail=b"\xff\xd8best")]))
    [o] = [r["o"] for r in store.read("object_all", room=ROOM)]
    assert bytes(o["thumbnail"]) == b"\xff\xd8best" and o["observations"] == 3


def test_a_folded_node_takes_its_appearance_with_it(store):
    hist = hist_of({30: 500})
    left = obj("l", "dining table", (-1.0, 0.0, 1.0), size=(0.8, 0.8, 0.1), hist=hist, colour="brown")
    right = obj("r", "dining table", (1.0, 0.0, 1.0), size=(0.8, 0.8, 0.1), hist=hist, colour="brown")
    merge_local_graph(store, graph([left]))
    merge_local_graph(store, graph([right]))
    whole = obj("w", "dining table", (0.0, 0.0, 1.0), size=(2.4, 0.8, 0.1), hist=hist, colour="brown")
    assert merge_local_graph(store, graph([whole])).absorbed == 1
    counts = node_counts(store)
    assert counts["Object"] == 1 and counts["Appearance"] == 1
    [table] = [r["o"] for r in store.read("object_all", room=ROOM)]
    assert np.allclose(unpack_hist(table["hist"]), 3 * hist)


def test_a_schema_1_store_is_migrated_and_keeps_answering(store, monkeypatch, caplog):
    """Objects written the old way (bytes on the record, version 1) move to Appearance nodes."""
    monkeypatch.setattr(store_module, "MIGRATION_BATCH", 2)   # several batches
    h = hist_of({5: 10, 9: 30})
    merge_local_graph(store, graph([obj("x", "chair", (5.0, 0.0, 5.0))]))   # creates the room
    for i in range(5):
        store.run_raw("MATCH (r:Room {id: $room}) CREATE (o:Object) SET o = $props "
                      "CREATE (r)-[:CONTAINS]->(o)",
                      {"room": ROOM, "props": {"id": f"old-{i}", "room": ROOM, "label": "bowl", "labels": ["bowl"],
                                               "scores": [0.8], "score": 0.8, "x": float(i), "y": 0.0, "z": 1.0,
                                               "var": [0.01] * 3, "n_points": 50, "size": [0.1 + i / 10] * 3,
                                               "volume": (0.1 + i / 10) ** 3, "box_centre": [float(i), 0.0, 1.0],
                                               "colour": "white", "first_frame": 0, "last_frame": 0,
                                               "observations": 1, "n_frames": 1,
                                               "hist": pack_hist(h), "thumbnail": b"\xff\xd8old" + bytes([i])}},
                      write=True)
    store.run_raw("MATCH (a:Appearance) WHERE a.id <> $keep DETACH DELETE a", {"keep": "none"}, write=True)
    store.write("schema_version_set", version=1)
    store._schema_checked = False

    with caplog.at_level("WARNING", logger="sg3d.store"):
        store.ensure_schema()
    n_tallies = store.run_raw("MATCH (t:Tally) RETURN count(t)")[1][0][0]
    assert [r.getMessage() for r in caplog.records] == [
        "upgraded the store from schema 1 to 3: moved 5 objects' histograms and thumbnails to Appearance "
        f"nodes, recounted {n_tallies} tallies"]

    assert store.read("schema_version")[0]["version"] == store_module.SCHEMA_VERSION == 3
    assert all("hist" not in o and "thumbnail" not in o for o in raw_objects(store))
    assert node_counts(store)["Appearance"] == 5        # the migrated ones (the chair's was deleted above)
    full = {o["id"]: o for o in (r["o"] for r in store.read("object_all", room=ROOM))}
    assert np.allclose(unpack_hist(full["old-3"]["hist"]), h) and bytes(full["old-3"]["thumbnail"]) == b"\xff\xd8old\x03"
    assert answer(store, "how many bowls are there?").value == 5     # tallies recounted
    a = answer(store, "show me the biggest bowl")
    assert a.ok and a.value["id"] == "old-4" and a.thumbnail == b"\xff\xd8old\x04"
    # a merge onto a migrated node combines the migrated histogram
    report = merge_local_graph(store, graph([obj("n", "bowl", (2.0, 0.0, 1.0), labels=["bowl"], hist=h,
                                                 colour="white", size=(0.3, 0.3, 0.3))]))
    assert report.updated == 1
    after = {r["o"]["id"]: r["o"] for r in store.read("object_all", room=ROOM)}
    assert report.node_ids["n"] == "old-2" and np.allclose(unpack_hist(after["old-2"]["hist"]), 2 * h)
