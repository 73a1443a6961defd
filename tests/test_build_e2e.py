"""End to end on the real kitchen: `sg3d build` of a slice into a real embedded store, twice."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest


def sg3d(home, *args, timeout=600):
    env = dict(os.environ, SG3D_HOME=str(home))
    env.pop("SG3D_URI", None)
    return subprocess.run([sys.executable, "-m", "sg3d", *args], capture_output=True, text=True,
                          env=env, timeout=timeout)


@pytest.fixture(scope="module")
def home(tmp_path_factory):
    from graphdb.embedded import EmbeddedServer

    home = tmp_path_factory.mktemp("build-home")
    yield home
    EmbeddedServer(home).stop()


def _build(home, kitchen_dir, *extra):
    out = sg3d(home, "build", str(kitchen_dir), "--room", "slice", "--building", "test",
               "--start", "0", "--stop", "120", "--json", *extra)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_build_twice_gives_identical_counts(home, kitchen_dir):
    first = _build(home, kitchen_dir)
    assert first["frames"]["read"] == 120
    assert first["placement"] == {"how": "reference room of the building"}
    assert first["graph"]["merged_groups"] >= 1
    assert first["graph"]["room_objects"] > 0
    second = _build(home, kitchen_dir)
    assert second["graph"]["merged_groups"] == 0
    assert second["graph"]["skipped_groups"] == first["graph"]["merged_groups"]
    assert second["graph"]["room_objects"] == first["graph"]["room_objects"]
    assert second["graph"]["room_relations"] == first["graph"]["room_relations"]

    labels = json.loads(sg3d(home, "cypher", "MATCH (o:Object) WHERE o.room = 'test/slice' "
                                            "RETURN o.label AS label", "--json").stdout)
    # the first frames look at the dining table and its chairs
    assert {"dining table", "chair"} & {row["label"] for row in labels}

    exported = json.loads(sg3d(home, "export", "--building", "test", "--room", "slice").stdout)
    assert len(exported["nodes"]) == first["graph"]["room_objects"]
    assert len(exported["edges"]) == first["graph"]["room_relations"]
    graphml = sg3d(home, "export", "--building", "test", "--format", "graphml").stdout
    ns = {"g": "http://graphml.graphdrawing.org/xmlns"}
    assert len(ET.fromstring(graphml).findall(".//g:node", ns)) == first["graph"]["room_objects"]


def test_resume_continues_after_the_last_merged_group(home, kitchen_dir):
    out = sg3d(home, "build", str(kitchen_dir), "--room", "resumed", "--building", "test",
               "--stop", "60", "--json")
    assert out.returncode == 0, out.stderr
    out = sg3d(home, "build", str(kitchen_dir), "--room", "resumed", "--building", "test",
               "--stop", "60", "--resume", "--json")
    summary = json.loads(out.stdout)
    assert summary["frames"]["read"] < 60  # frames up to the last merged group were not read again


def test_bad_sequence_is_one_clear_line(home, tmp_path):
    out = sg3d(home, "build", str(tmp_path / "nope"), "--room", "x")
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1 and "not found" in out.stderr


def test_a_second_room_takes_the_given_transform(home, kitchen_dir, tmp_path):
    transform = tmp_path / "t.txt"
    transform.write_text("0 -1 0 1\n1 0 0 2\n0 0 1 0\n0 0 0 1\n")
    out = sg3d(home, "build", str(kitchen_dir), "--room", "other", "--building", "test",
               "--start", "0", "--stop", "40", "--transform", str(transform), "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["placement"] == {"how": "transform file"}
    rooms = json.loads(sg3d(home, "rooms", "--building", "test", "--json").stdout)
    placed = {r["name"]: r for r in rooms}
    assert placed["other"]["to_building"][0] == [0.0, -1.0, 0.0, 1.0]
    assert placed["slice"]["to_building"][0] == [1.0, 0.0, 0.0, 0.0]
