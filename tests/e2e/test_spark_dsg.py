"""spark_dsg (Hydra's format): export the kitchen graph, load it with spark_dsg itself, import it
into a new building, and import a graph written the way Hydra writes one."""
from __future__ import annotations

import json

import numpy as np
import pytest

from tests.cli_helpers import sg3d

dsg = pytest.importorskip("spark_dsg", reason="spark-dsg (PyPI) has no wheel for this platform")

from sg3d.formats.spark_dsg import BUILDINGS, OBJECTS, ROOMS, STRUCTURE  # noqa: E402  (layer ids 2, 4, 5, 1)


@pytest.fixture(scope="module")
def home(tmp_path_factory, kitchen_dir):
    """A store holding a real kitchen graph (80 frames, 3d-full)."""
    from sg3d.graphdb.embedded import EmbeddedServer

    home = tmp_path_factory.mktemp("spark-home")
    r = sg3d(home, "build", kitchen_dir, "--room", "kitchen", "--building", "lab", "--start", 0, "--stop", 80,
             "--json")
    assert r.returncode == 0, r.stderr
    yield home
    EmbeddedServer(home).stop()


def _objects(home, building):
    r = sg3d(home, "export", "--building", building)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_export_loads_in_spark_dsg_and_imports_back(home, tmp_path):
    ours = _objects(home, "lab")
    assert ours["nodes"], "the kitchen build found no object"
    out = tmp_path / "kitchen_dsg.json"
    r = sg3d(home, "export", "--building", "lab", "--format", "spark-dsg", "--out", out)
    assert r.returncode == 0, r.stderr

    G = dsg.DynamicSceneGraph.load(str(out))
    layers = {k.layer: G.get_layer(k.layer).num_nodes() for k in G.layer_keys}
    structure = [n for n in ours["nodes"] if n.get("layer") == "structure"]
    assert structure, "the kitchen build found no floor, wall or surface"
    assert layers[OBJECTS] == len(ours["nodes"]) - len(structure)
    assert layers[STRUCTURE] == len(structure)
    assert layers[ROOMS] == 1 and layers[BUILDINGS] == 1
    names = G.get_labelspace(2, 0).labels_to_names
    by_id = {n["id"]: n for n in ours["nodes"]}
    room = next(iter(G.get_layer(ROOMS).nodes))
    assert room.attributes.name == "kitchen"
    assert room.get_parent() == next(iter(G.get_layer(BUILDINGS).nodes)).id.value
    for node in list(G.get_layer(OBJECTS).nodes) + list(G.get_layer(STRUCTURE).nodes):
        a = node.attributes
        mine = by_id[a.metadata.get()["sg3d"]["id"]]
        assert names[a.semantic_label] == mine["label"]
        assert a.name == mine["name"]
        np.testing.assert_allclose(a.position, (mine["x"], mine["y"], mine["z"]), atol=1e-9)
        np.testing.assert_allclose(a.bounding_box.dimensions, mine["size"], atol=1e-5)
        if node.layer == OBJECTS:
            assert node.get_parent() == room.id.value   # interlayer edge object -> room
    pairs = {tuple(sorted((e["s"], e["o"]))) for e in ours["edges"]}
    relation_edges = [e for e in G.edges if e.info.metadata.get().get("relations")]
    assert len(relation_edges) == len(pairs)
    assert sum(len(e.info.metadata.get()["relations"]) for e in relation_edges) == len(ours["edges"])

    r = sg3d(home, "import", "--format", "spark-dsg", out, "--building", "copy", "--json")
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    assert [x["room"] for x in report["rooms"]] == ["copy/kitchen"]
    copy = _objects(home, "copy")
    assert len(copy["nodes"]) == len(ours["nodes"])
    a = sorted((n["label"], n["x"], n["y"], n["z"]) for n in ours["nodes"])
    b = sorted((n["label"], n["x"], n["y"], n["z"]) for n in copy["nodes"])
    assert [x[0] for x in a] == [x[0] for x in b]
    assert np.abs(np.array([x[1:] for x in a]) - np.array([x[1:] for x in b])).max() < 0.01
    assert {(e["type"]) for e in copy["edges"]} == {e["type"] for e in ours["edges"]}
    assert len(copy["edges"]) == len(ours["edges"])

    again = json.loads(sg3d(home, "import", out, "--building", "copy", "--json").stdout)
    assert again["rooms"][0]["skipped"] and again["rooms"][0]["room_objects"] == len(copy["nodes"])


def test_import_of_a_hydra_style_graph(home, tmp_path):
    """No sg3d metadata: labels from the labelspace, rooms from the rooms layer, colour from RGB."""
    G = dsg.DynamicSceneGraph()
    G.set_labelspace(dsg.Labelspace({0: "chair", 5: "couch"}), 2)
    b = dsg.SemanticNodeAttributes()
    b.name = "office"
    b.position = np.zeros(3)
    G.add_node(dsg.DsgLayers.BUILDINGS, dsg.NodeSymbol("B", 0), b)
    for k, (label, pos, rgb) in enumerate([(0, (1.0, 2.0, 0.4), (200, 20, 20)), (5, (3.0, 1.0, 0.5), (30, 60, 230))]):
        a = dsg.ObjectNodeAttributes()
        a.semantic_label = label
        a.position = np.array(pos)
        a.bounding_box = dsg.BoundingBox(np.array([0.5, 0.5, 0.9], np.float32), np.array(pos, np.float32))
        a.color = np.array(rgb, np.uint8)
        G.add_node(dsg.DsgLayers.OBJECTS, dsg.NodeSymbol("O", k), a)
    r = dsg.RoomNodeAttributes()
    r.name = "lounge"
    r.position = np.array([2.0, 1.5, 0.0])
    G.add_node(dsg.DsgLayers.ROOMS, dsg.NodeSymbol("R", 3), r)
    G.insert_edge(dsg.NodeSymbol("R", 3), dsg.NodeSymbol("O", 0))
    G.insert_edge(dsg.NodeSymbol("R", 3), dsg.NodeSymbol("O", 1))
    G.insert_edge(dsg.NodeSymbol("B", 0), dsg.NodeSymbol("R", 3))
    path = tmp_path / "hydra_dsg.json"
    G.save(str(path), include_mesh=False)

    r = sg3d(home, "import", path, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["rooms"][0]["room"] == "office/lounge"
    nodes = _objects(home, "office")["nodes"]
    assert sorted((n["label"], n["colour"], round(n["x"], 3)) for n in nodes) == [("chair", "red", 1.0),
                                                                                  ("couch", "blue", 3.0)]

    bad = tmp_path / "not_a_graph.json"
    bad.write_text('{"nodes": 3}')
    r = sg3d(home, "import", bad)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "spark_dsg" in r.stderr


def test_3dssg_export(home, tmp_path):
    from sg3d.formats.threedssg import PREDICATE, RELATIONSHIPS

    ours = _objects(home, "lab")
    r = sg3d(home, "export", "--building", "lab", "--format", "3dssg", "--out", tmp_path / "ssg")
    assert r.returncode == 0, r.stderr
    objects = json.loads((tmp_path / "ssg" / "objects.json").read_text())
    rels = json.loads((tmp_path / "ssg" / "relationships.json").read_text())
    assert [s["scan"] for s in objects["scans"]] == ["lab/kitchen"] == [s["scan"] for s in rels["scans"]]
    objs = objects["scans"][0]["objects"]
    assert sorted(o["label"] for o in objs) == sorted(n["label"] for n in ours["nodes"])
    number = {o["sg3d_id"]: int(o["id"]) for o in objs}
    assert rels["scans"][0]["objects"] == {o["id"]: o["label"] for o in objs}
    got = {tuple(x) for x in rels["scans"][0]["relationships"]}
    want = {(number[e["s"]], number[e["o"]], RELATIONSHIPS.index(PREDICATE[e["type"]]), PREDICATE[e["type"]])
            for e in ours["edges"] if e["type"] in PREDICATE}
    assert got == want and want, "every mappable relation is exported once"
    on = [x for x in got if x[3] == "standing on"]
    assert len(on) == sum(e["type"] == "ON" for e in ours["edges"]) and all(x[2] == 15 for x in on)
