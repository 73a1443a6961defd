"""Nothing written where the user did not say, nothing flooded onto a terminal, warnings where
a result would mislead, and one room removable on its own (a real store, the real CLI)."""
from __future__ import annotations

import base64
import json
import os
import pty
import subprocess
import sys
import tempfile

import cv2
import numpy as np
import pytest
from click.testing import CliRunner

from tests.cli_helpers import sg3d_env
from tests.serve_helpers import kitchen_body

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _jpeg() -> str:
    ok, buf = cv2.imencode(".jpg", np.full((40, 40, 3), 200, np.uint8))
    return base64.b64encode(buf.tobytes()).decode()


@pytest.fixture
def two_rooms(store):
    from sg3d.app.ingest import IngestRequest, ingest_graph

    kitchen = kitchen_body("k-1", room="kitchen")
    for o in kitchen["graph"]["objects"]:
        o["thumbnail"] = _jpeg()
    ingest_graph(store, IngestRequest.model_validate(kitchen))
    ingest_graph(store, IngestRequest.model_validate(kitchen_body("p-1", room="pantry")))
    return store


def _cli(embedded_home, *args, **kw):
    from sg3d.cli import cli

    return CliRunner().invoke(cli, ["--home", str(embedded_home), *args], **kw)


def _count(store, statement, **params):
    return store.run_raw(statement, params)[1][0][0]


def test_rooms_delete_removes_one_room_only(two_rooms, embedded_home):
    store = two_rooms
    kept = _cli(embedded_home, "rooms", "--building", "home", "delete", "kitchen", input="n\n")
    assert kept.exit_code != 0 and _count(store, "MATCH (o:Object) WHERE o.room = 'home/kitchen' RETURN count(o)") == 10
    pantry_before = [_count(store, f"MATCH (n:{label}) WHERE n.room = 'home/pantry' RETURN count(n)")
                     for label in ("Object", "Tally", "MergeLog")]
    r = _cli(embedded_home, "rooms", "--building", "home", "delete", "kitchen", "--yes")
    assert r.exit_code == 0 and "10 objects" in r.output, r.output
    for label in ("Object", "Tally", "MergeLog", "Scan"):
        assert _count(store, f"MATCH (n:{label}) WHERE n.room = 'home/kitchen' RETURN count(n)") == 0, label
    assert _count(store, "MATCH (r:Room {id: 'home/kitchen'}) RETURN count(r)") == 0
    assert _count(store, "MATCH (a:Appearance) RETURN count(a)") == 10       # the pantry's only
    assert [_count(store, f"MATCH (n:{label}) WHERE n.room = 'home/pantry' RETURN count(n)")
            for label in ("Object", "Tally", "MergeLog")] == pantry_before
    missing = _cli(embedded_home, "rooms", "--building", "home", "delete", "kitchen", "--yes")
    assert missing.exit_code == 2 and "no room" in missing.output

    from sg3d.app.ingest import IngestRequest, ingest_graph

    again = ingest_graph(store, IngestRequest.model_validate(kitchen_body("k-1", room="kitchen")))
    assert again["created"] == 10                      # its merge log went with it


def test_ask_and_plan_write_no_file_without_out(two_rooms, embedded_home, tmp_path, monkeypatch):
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    r = _cli(embedded_home, "ask", "show me the biggest cup", "--room", "kitchen", "--building", "home")
    assert r.exit_code == 0, r.output
    assert "--out FILE" in r.output and not any(ln.startswith("picture:") for ln in r.output.splitlines())
    p = _cli(embedded_home, "plan", "put the red cup in the sink", "--room", "kitchen", "--building", "home")
    assert p.exit_code == 0, p.output
    assert "--out DIR" in p.output
    assert list(scratch.iterdir()) == []
    out = tmp_path / "cup.png"
    r = _cli(embedded_home, "ask", "show me the biggest cup", "--room", "kitchen", "--building", "home",
             "--out", str(out))
    assert out.exists() and f"picture: {out}" in r.output


def test_export_to_a_terminal_prints_a_summary(two_rooms, embedded_home):
    env = sg3d_env(embedded_home, PYTHONPATH=REPO)

    def on_terminal(*args):
        leader, follower = pty.openpty()
        proc = subprocess.run([sys.executable, "-m", "sg3d", "export", "--building", "home", "--room", "kitchen",
                               *args], stdout=follower, stderr=subprocess.PIPE, env=env, timeout=300)
        os.close(follower)
        chunks = []
        while True:
            try:
                data = os.read(leader, 65536)
            except OSError:
                break
            if not data:
                break
            chunks.append(data)
        os.close(leader)
        return proc.returncode, b"".join(chunks).decode()

    code, text = on_terminal()
    assert code == 0 and "10 nodes" in text and "--out -" in text and len(text) < 400
    code, text = on_terminal("--out", "-")
    assert code == 0 and json.loads(text)["nodes"]


def test_eval_warns_when_the_ground_truth_lies_elsewhere(two_rooms, embedded_home, tmp_path):
    elsewhere = {"objects": [{"id": f"g{i}", "category": "cup", "coco_category": "cup",
                              "world_position": [50.0 + i, 40.0, 3.0]} for i in range(6)]}
    gt = tmp_path / "gt.json"
    gt.write_text(json.dumps(elsewhere))
    r = _cli(embedded_home, "eval", "--gt", str(gt), "--room", "kitchen", "--building", "home", "--no-vqa",
             "--json")
    assert r.exit_code == 0, r.output
    assert "6 of 6 ground-truth objects lie outside" in r.output
    here = {"objects": [{"id": "g0", "category": "cup", "coco_category": "cup", "world_position": [0.0, 0.0, 0.8]}]}
    gt.write_text(json.dumps(here))
    r = _cli(embedded_home, "eval", "--gt", str(gt), "--room", "kitchen", "--building", "home", "--no-vqa",
             "--json")
    assert "outside" not in r.output
