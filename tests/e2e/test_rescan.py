"""Re-scans (issue #17) on hand-made scenes: the free-space rule, removed and moved objects in the
real store, tallies after a removal, history, idempotent re-runs. The kitchen scans on real
frames are in tests/quality/kitchen/test_rescan_kitchen.py."""
from __future__ import annotations

import json
from collections import Counter

import numpy as np
import pytest
from click.testing import CliRunner

from sg3d.app.ask import ask
from sg3d.app.changes import room_changes
from sg3d.core.model import KnownObject, ScanInfo
from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.rescan import known_objects
from sg3d.graphdb.values import room_id
from sg3d.ingest.objects.existence import DEPTH_FACTOR, View
from sg3d.ingest.objects.rescan import empty_places, place_seen_empty
from sg3d.queries.vqa import answer
from tests.factories import graph, obj

K = np.array([[585.0, 0, 320], [0, 585, 240], [0, 0, 1]])
TABLE_Z = 0.8
MUG = dict(mean=(0.0, 0.0, 0.85), size=(0.09, 0.09, 0.1))
ROOM = room_id("home", "kitchen")


def camera_at(target, index: int = 0, back=(0.0, -1.0, 1.0)) -> np.ndarray:
    """Camera-to-world pose of a camera at target + back looking at target (world z up)."""
    target = np.asarray(target, float)
    eye = target + np.asarray(back, float)
    fwd = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(fwd, [0, 0, 1.0])
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, np.cross(fwd, right), fwd, eye
    return pose


def view(index: int, pose: np.ndarray, boxes=()) -> View:
    """A frame whose depth shows the table plane z = TABLE_Z and the given boxes (centre, size)."""
    h, w = 480 // DEPTH_FACTOR, 640 // DEPTH_FACTOR
    vs, us = np.mgrid[0:h, 0:w]
    rays = np.stack([(us * DEPTH_FACTOR - K[0, 2]) / K[0, 0], (vs * DEPTH_FACTOR - K[1, 2]) / K[1, 1],
                     np.ones((h, w))], -1)
    dirs, o = rays @ pose[:3, :3].T, pose[:3, 3]
    depth = np.where(dirs[..., 2] < 0, (TABLE_Z - o[2]) / np.where(dirs[..., 2] < 0, dirs[..., 2], -1), 0.0)
    for centre, size in boxes:
        lo, hi = np.asarray(centre) - np.asarray(size) / 2, np.asarray(centre) + np.asarray(size) / 2
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (lo - o) / dirs, (hi - o) / dirs
        t_in, t_out = np.nanmax(np.minimum(t1, t2), -1), np.nanmin(np.maximum(t1, t2), -1)
        hit = (t_out > t_in) & (t_in > 0) & ((depth <= 0) | (t_in < depth))
        depth = np.where(hit, t_in, depth)
    return View(index, K, pose, (640, 480), depth.astype(np.float32))


MUG_BOX = KnownObject("m", MUG["mean"], MUG["size"])


def test_place_seen_empty_tells_free_space_from_the_object_and_from_an_occluder():
    pose = camera_at(MUG["mean"])
    assert place_seen_empty(MUG_BOX, np.eye(3), view(1, pose)) is True
    assert place_seen_empty(MUG_BOX, np.eye(3), view(2, pose, [(MUG["mean"], (0.08, 0.08, 0.1))])) is False
    # a board between the camera and the mug's place: the frame cannot tell
    assert place_seen_empty(MUG_BOX, np.eye(3), view(3, pose, [((0, -0.5, 1.3), (0.4, 0.05, 0.4))])) is None
    # looking elsewhere: no evidence either way
    assert place_seen_empty(MUG_BOX, np.eye(3), view(4, camera_at((3.0, 0.0, 0.85)))) is None


def test_an_unnamed_object_is_judged_on_its_own_surface_points():
    """An L-shaped thing (a board standing on the table with a foot): its box's core is free space
    while it stands there, so the box rule would call it gone; its surface points tell."""
    # the upright part stands at the back of the box, the foot reaches forward along the table
    board = ((0.0, 0.19, 0.95), (0.3, 0.02, 0.3))
    xs, zs = np.meshgrid(np.linspace(-0.14, 0.14, 6), np.linspace(0.82, 1.08, 5))
    points = np.stack([xs.ravel(), np.full(xs.size, 0.18), zs.ravel()], 1)
    seg = KnownObject("b", (0.0, 0.1, 0.95), (0.3, 0.2, 0.3), tuple(points.ravel()))
    pose = camera_at((0.0, 0.0, 0.95))
    assert place_seen_empty(KnownObject("b", seg.box_centre, seg.size), np.eye(3), view(1, pose, [board])) is True
    assert place_seen_empty(seg, np.eye(3), view(1, pose, [board])) is False
    assert place_seen_empty(seg, np.eye(3), view(2, pose)) is True
    assert place_seen_empty(seg, np.eye(3), view(3, camera_at((3.0, 0.0, 0.85)))) is None


def tallies(store) -> Counter:
    _, rows = store.run_raw("MATCH (t:Tally) WHERE t.n <> 0 AND t.colour = '' RETURN t.label, t.n")
    return Counter({r[0]: r[1] for r in rows})


def objects(store) -> dict[str, dict]:
    _, rows = store.run_raw("MATCH (o:Object) RETURN o {.*}")
    return {r[0]["id"]: r[0] for r in rows}


def scan(graph_, sid: str, at: float, known=(), views=()):
    graph_.scan = ScanInfo(sid, at)
    graph_.key = f"{sid}:0-10"
    graph_.empty_places = empty_places(known, views, np.eye(3))
    return graph_


def first_scan(store):
    mug = obj("m", "cup", MUG["mean"], size=MUG["size"], colour="red")
    book = obj("b", "book", (1.0, 0.0, 0.82), size=(0.2, 0.15, 0.04), colour="blue")
    r = merge_local_graph(store, scan(graph([mug, book]), "s1", 100.0))
    return r.node_ids["m"], r.node_ids["b"]


def test_a_mug_whose_place_is_seen_empty_is_removed_kept_out_of_counts_and_a_rerun_changes_nothing(store):
    mug_id, book_id = first_scan(store)
    assert tallies(store) == Counter({"cup": 1, "book": 1})
    known = known_objects(store, ROOM)
    frames = [view(i, camera_at(MUG["mean"], back=(0.1 * i, -1.0, 1.0))) for i in range(3)]
    book = obj("b2", "book", (1.0, 0.0, 0.82), size=(0.2, 0.15, 0.04), colour="blue")
    g2 = scan(graph([book]), "s2", 200.0, known, frames)
    assert set(g2.empty_places) == {mug_id}
    report = merge_local_graph(store, g2)
    assert (report.removed, report.updated, report.created) == (1, 1, 0)
    after = objects(store)
    assert set(after) == {mug_id, book_id}                      # never deleted
    assert after[mug_id]["removed_at"] == 200.0 and after[mug_id]["removed_scan"] == "s2"
    assert after[mug_id]["empty_frames"] == [0, 1, 2]
    assert after[book_id].get("removed_at") is None and after[book_id]["scans"] == ["s1", "s2"]
    assert (after[book_id]["first_seen"], after[book_id]["last_seen"]) == (100.0, 200.0)
    assert tallies(store) == Counter({"book": 1})
    assert store.read("object_count", room=ROOM)[0]["n"] == 1
    assert answer(store, "how many cups are there?").value == 0
    assert answer(store, "how many books are there?").value == 1
    # the same scan again: skipped under its key, nothing changes
    assert merge_local_graph(store, scan(graph([book]), "s2", 200.0, known, frames)).skipped
    assert objects(store) == after and tallies(store) == Counter({"book": 1})

    changes = room_changes(store, "kitchen", "home")
    assert changes["scans"] == ["s2"] and (changes["moved"], changes["added"]) == ([], [])
    assert [(o["id"], o["label"], o["name"]) for o in changes["removed"]] == [(mug_id, "cup", "cup")]
    assert changes["removed"][0]["z"] == pytest.approx(0.85)
    assert room_changes(store, "kitchen", "home", since="s1")["removed"] == changes["removed"]
    assert room_changes(store, "kitchen", "home", since="s2")["removed"] == []
    gone = ask(store, "What is gone?").answer
    assert gone.ok and "cup" in gone.text and "book" not in gone.text
    # the queries read a change question and leave it to the application (no call back into it)
    read = answer(store, "What is gone?")
    assert not read.ok and read.change is not None and read.change.form.op == "gone" and "sg3d ask" in read.text
    changed = ask(store, "what changed in the kitchen?").answer
    assert changed.ok and changed.value["removed"][0]["id"] == mug_id and "gone: the cup" in changed.text
    before = ask(store, "where was the cup before?").answer
    assert before.ok and "(0.00, 0.00, 0.85)" in before.text and "now gone" in before.text

    # the formats that describe the scene as it stands leave the removed cup out; JSON keeps it
    from sg3d.app.graph import fetch_named_graph, render_graph

    exported = fetch_named_graph(store, "home", "kitchen")
    assert mug_id in {n.id for n in exported.nodes}
    assert '"label": "cup"' not in render_graph(exported, "3dssg")
    assert "cup" not in render_graph(exported, "spark-dsg") and "book" in render_graph(exported, "spark-dsg")


def test_changes_command_prints_json_and_refuses_an_unknown_scan(store, embedded_home):
    mug_id, book_id = first_scan(store)
    runner = CliRunner()
    from sg3d.cli import cli

    out = runner.invoke(cli, ["--home", str(embedded_home), "changes", "--room", "kitchen", "--building", "home",
                              "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert sorted(o["id"] for o in data["added"]) == sorted([mug_id, book_id])   # the first scan added both
    assert all(set(o) >= {"id", "name", "label", "x", "y", "z"} for o in data["added"])
    assert (data["moved"], data["removed"]) == ([], [])
    bad = runner.invoke(cli, ["--home", str(embedded_home), "changes", "--room", "kitchen", "--building", "home",
                              "--since", "nope"])
    assert bad.exit_code == 2 and "no scan 'nope'" in bad.output


def test_a_scan_that_fails_while_closing_leaves_the_previous_state(store, monkeypatch):
    mug_id, _ = first_scan(store)
    before, counted = objects(store), tallies(store)
    frames = [view(i, camera_at(MUG["mean"], back=(0.1 * i, -1.0, 1.0))) for i in range(3)]
    g2 = scan(graph([obj("b2", "book", (1.0, 0.0, 0.82), size=(0.2, 0.15, 0.04), colour="blue")]), "s2", 200.0,
              known_objects(store, ROOM), frames)
    import sg3d.graphdb.rescan as rescan_module

    real_close = rescan_module.close_scan

    def crash(tx, *args):
        real_close(tx, *args)           # the removal is written, then the process dies
        raise RuntimeError("crash mid-scan")

    monkeypatch.setattr(rescan_module, "close_scan", crash)
    with pytest.raises(RuntimeError):
        merge_local_graph(store, g2)
    assert objects(store) == before and tallies(store) == counted
    monkeypatch.setattr(rescan_module, "close_scan", real_close)
    assert merge_local_graph(store, g2).removed == 1          # the same scan again completes it


def test_a_partial_rescan_that_never_looks_at_the_mug_keeps_it(store):
    mug_id, _ = first_scan(store)
    known = known_objects(store, ROOM)
    frames = [view(i, camera_at((1.0, 0.0, 0.82), back=(0.5, -1.0, 1.0))) for i in range(3)]
    book = obj("b2", "book", (1.0, 0.0, 0.82), size=(0.2, 0.15, 0.04), colour="blue")
    report = merge_local_graph(store, scan(graph([book]), "s2", 200.0, known, frames))
    assert report.removed == 0
    assert objects(store)[mug_id].get("removed_at") is None
    assert tallies(store) == Counter({"cup": 1, "book": 1})


def test_a_mug_one_metre_away_with_its_old_place_seen_empty_moves_the_node(store):
    mug_id, book_id = first_scan(store)
    known = known_objects(store, ROOM)
    frames = [view(i, camera_at(MUG["mean"], back=(0.1 * i, -1.0, 1.0))) for i in range(3)]
    moved = obj("m2", "cup", (0.0, 1.0, 0.85), size=MUG["size"], colour="red")
    book = obj("b2", "book", (1.0, 0.0, 0.82), size=(0.2, 0.15, 0.04), colour="blue")
    report = merge_local_graph(store, scan(graph([moved, book]), "s2", 200.0, known, frames))
    assert (report.moved, report.created, report.removed) == (1, 0, 0)
    after = objects(store)
    assert set(after) == {mug_id, book_id}                      # no duplicate, no ghost
    mug = after[mug_id]
    assert mug.get("removed_at") is None and mug["y"] == pytest.approx(1.0)
    assert mug["history_scans"] == ["s2"] and mug["history_at"] == [200.0] and mug["history_y"] == [pytest.approx(0.0)]
    assert mug["moved_scan"] == "s2" and mug["scans"] == ["s1", "s2"]
    assert tallies(store) == Counter({"cup": 1, "book": 1})
    changes = room_changes(store, "kitchen", "home")
    assert [o["id"] for o in changes["moved"]] == [mug_id] and (changes["added"], changes["removed"]) == ([], [])
    assert changes["moved"][0]["from"] == {"x": 0.0, "y": 0.0, "z": 0.85} and changes["moved"][0]["y"] == 1.0
    before = ask(store, "where was the cup before?").answer
    assert before.ok and "was at (0.00, 0.00, 0.85); now at (0.00, 1.00, 0.85)" in before.text


def test_without_empty_place_evidence_a_far_mug_is_a_new_object(store):
    mug_id, _ = first_scan(store)
    far = obj("m2", "cup", (0.0, 1.0, 0.85), size=MUG["size"], colour="red")
    report = merge_local_graph(store, scan(graph([far]), "s2", 200.0))
    assert (report.moved, report.created) == (0, 1)
    assert objects(store)[mug_id].get("removed_at") is None
