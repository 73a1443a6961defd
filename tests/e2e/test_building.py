"""Linking rooms into a building on a real store, with a known room-to-room motion."""
from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from sg3d.graphdb.building import TransformError, align_rooms, link_rooms, list_rooms, load_transform
from sg3d.graphdb.merge import merge_local_graph
from sg3d.merge.align import AlignmentError, estimate_rigid_transform, ransac_rigid
from tests.factories import graph, hist_of, obj

ANGLE = np.radians(30.0)
# room B's frame -> room A's: 30° about the up axis (z here) and a shift through the doorway
T_TRUE = np.array([[np.cos(ANGLE), -np.sin(ANGLE), 0.0, 2.0],
                   [np.sin(ANGLE), np.cos(ANGLE), 0.0, -1.0],
                   [0.0, 0.0, 1.0, 0.1],
                   [0.0, 0.0, 0.0, 1.0]])

# (label, bin, position in room A's frame): seen from both rooms
SHARED = [("cabinet", 10, (1.0, 0.0, 0.5)), ("plant", 20, (2.5, 1.0, 0.3)),
          ("clock", 30, (1.5, 2.0, 1.8)), ("chair", 40, (3.0, -1.0, 0.45)),
          ("shelf", 50, (0.5, 1.5, 1.2))]
ONLY_A = [("sofa", 60, (-2.0, 3.0, 0.4)), ("television", 70, (-3.0, -2.0, 1.0))]
ONLY_B = [("bed", 80, (4.0, 4.0, 0.5)), ("desk", 90, (6.0, 0.0, 0.7)),
          # same label and colour as the shared chair but elsewhere: a wrong candidate pair
          ("chair", 40, (5.0, -3.0, 0.45))]


def _build_rooms(store, noise_m: float = 0.01, seed: int = 1):
    rng = np.random.default_rng(seed)
    inv = np.linalg.inv(T_TRUE)
    a = [obj(f"a{k}", lbl, pos, hist=hist_of({b: 100})) for k, (lbl, b, pos) in enumerate(SHARED + ONLY_A)]
    b = []
    for k, (lbl, bn, pos) in enumerate(SHARED):
        p_b = inv[:3, :3] @ np.array(pos) + inv[:3, 3] + rng.normal(0.0, noise_m, 3)
        b.append(obj(f"b{k}", lbl, tuple(p_b), hist=hist_of({bn: 100})))
    b += [obj(f"bx{k}", lbl, pos, hist=hist_of({bn: 100})) for k, (lbl, bn, pos) in enumerate(ONLY_B)]
    merge_local_graph(store, graph(a, room="kitchen", building="home"))
    merge_local_graph(store, graph(b, room="hall", building="home"))


def _rotation_error_deg(R1, R2) -> float:
    c = (np.trace(R1.T @ R2) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def _count(store, text):
    return store.run_raw(text)[1][0][0]


def test_kabsch_recovers_an_exact_motion():
    src = np.random.default_rng(0).uniform(-2, 2, (6, 3))
    dst = src @ T_TRUE[:3, :3].T + T_TRUE[:3, 3]
    assert np.allclose(estimate_rigid_transform(src, dst), T_TRUE, atol=1e-9)


def test_ransac_ignores_outlier_pairs():
    rng = np.random.default_rng(3)
    src = rng.uniform(-3, 3, (10, 3))
    dst = src @ T_TRUE[:3, :3].T + T_TRUE[:3, 3]
    dst[[2, 7]] += [1.5, -2.0, 0.5]          # two wrong correspondences
    T, inliers = ransac_rigid(src, dst, iters=300, inlier_m=0.05)
    assert inliers.sum() == 8 and not inliers[2] and not inliers[7]
    assert np.allclose(T, T_TRUE, atol=1e-6)


def test_align_rooms_recovers_the_known_transform(store):
    _build_rooms(store)
    al = align_rooms(store, "home/kitchen", "home/hall")
    assert np.linalg.norm(al.T[:3, 3] - T_TRUE[:3, 3]) < 0.05
    assert _rotation_error_deg(al.T[:3, :3], T_TRUE[:3, :3]) < 2.0
    assert len(al.pairs) == len(SHARED) and al.residual_rms_m < 0.03
    assert al.candidates > len(SHARED)        # the decoy chair was a candidate, not an inlier


def test_link_stores_transforms_and_links_shared_objects_once(store):
    _build_rooms(store)
    for _ in range(2):                         # a re-run replaces, never duplicates
        report = link_rooms(store, "home/kitchen", "home/hall")
        assert len(report.same_as) == len(SHARED)
    assert _count(store, "MATCH (:Object)-[s:SAME_AS]->(:Object) RETURN count(s)") == len(SHARED)
    # the reverse order replaces the same links as well
    link_rooms(store, "home/hall", "home/kitchen")
    assert _count(store, "MATCH (:Object)-[s:SAME_AS]->(:Object) RETURN count(s)") == len(SHARED)
    link_rooms(store, "home/kitchen", "home/hall")

    labels = store.run_raw("MATCH (a:Object)-[s:SAME_AS]->(b:Object) "
                           "RETURN a.label, b.label, a.room, b.room, s.distance")[1]
    assert all(la == lb and ra == "home/kitchen" and rb == "home/hall" and d < 0.1
               for la, lb, ra, rb, d in labels)
    assert sorted(r[0] for r in labels) == sorted(lbl for lbl, _, _ in SHARED)
    adj = store.run_raw("MATCH (a:Room)-[e:ADJACENT_TO]->(b:Room) "
                        "RETURN a.name, b.name, e.shared_objects, e.residual_m ORDER BY a.name")[1]
    assert [(r[0], r[1], r[2]) for r in adj] == [("hall", "kitchen", 5), ("kitchen", "hall", 5)]
    assert adj[0][3] < 0.03

    rooms = {r["name"]: r for r in list_rooms(store, "home")}
    assert np.allclose(rooms["kitchen"]["to_building"], np.eye(4))     # the reference room
    assert np.allclose(rooms["hall"]["to_building"], T_TRUE, atol=0.05)
    assert rooms["kitchen"]["objects"] == len(SHARED) + len(ONLY_A)
    assert rooms["hall"]["adjacent"] == ["kitchen"]


def test_link_with_a_user_transform_file(store, tmp_path):
    _build_rooms(store)
    path = tmp_path / "hall.txt"
    path.write_text("# hall -> kitchen\n" + "\n".join(" ".join(f"{v:.9f}" for v in row) for row in T_TRUE) + "\n")
    report = link_rooms(store, "home/kitchen", "home/hall", transform=load_transform(path))
    assert report.from_file and len(report.same_as) == len(SHARED) and report.residual_rms_m < 0.03


def test_too_few_shared_objects_is_a_clear_error(store):
    merge_local_graph(store, graph([obj("a", "sofa", (0, 0, 0), hist=hist_of({1: 9}))], room="r1", building="h"))
    merge_local_graph(store, graph([obj("b", "bed", (0, 0, 0), hist=hist_of({2: 9}))], room="r2", building="h"))
    with pytest.raises(AlignmentError, match="at least 3 shared objects"):
        align_rooms(store, "h/r1", "h/r2")


@pytest.mark.parametrize("text, message", [
    ("1 0 0\n0 1 0\n0 0 1\n", "expected 4 lines of 4 numbers"),
    ("1 0 0 0\n0 1 0 0\n0 0 1 0\n", "expected 4 lines of 4 numbers"),
    ("1 0 0 0\n0 1 x 0\n0 0 1 0\n0 0 0 1\n", "not a number"),
    ("2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n", "not a rotation"),
    ("1 0 0 0\n0 1 0 0\n0 0 1 0\n1 0 0 1\n", "last row"),
])
def test_load_transform_rejects_malformed_files(tmp_path, text, message):
    path = tmp_path / "t.txt"
    path.write_text(text)
    with pytest.raises(TransformError, match=message):
        load_transform(path)


def test_cli_rooms_and_link(store, monkeypatch, tmp_path):
    from sg3d.cli import cli
    from sg3d.settings import Settings

    _build_rooms(store)
    monkeypatch.setattr(Settings, "store", lambda self: store)
    monkeypatch.setattr(Settings, "reader", lambda self: store)
    runner = CliRunner()
    res = runner.invoke(cli, ["rooms", "link", "kitchen", "hall", "--building", "home", "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert data["pairs"] == 5 and data["same_as"] == 5 and data["residual_rms_m"] < 0.03
    res = runner.invoke(cli, ["rooms", "link", "kitchen", "home/hall", "--building", "home"])
    assert res.exit_code == 0, res.output
    assert "home/hall -> home/kitchen (aligned)" in res.output and "SAME_AS links: 5" in res.output
    res = runner.invoke(cli, ["rooms", "--building", "home", "--json"])
    assert res.exit_code == 0, res.output
    listed = {r["name"]: r for r in json.loads(res.stdout)}
    assert listed["hall"]["objects"] == 8 and listed["hall"]["to_building"] is not None
    res = runner.invoke(cli, ["rooms", "--building", "home"])
    assert "kitchen" in res.output and "adjacent: hall" in res.output
    bad = tmp_path / "bad.txt"
    bad.write_text("1 2 3\n")
    res = runner.invoke(cli, ["rooms", "link", "kitchen", "hall", "--building", "home", "--transform", str(bad)])
    assert res.exit_code == 2 and "expected 4 lines of 4 numbers" in res.output


def test_cli_rooms_building_given_before_link_is_the_links_building(store, monkeypatch):
    from sg3d.cli import cli
    from sg3d.settings import Settings

    _build_rooms(store)
    monkeypatch.setattr(Settings, "store", lambda self: store)
    runner = CliRunner()
    res = runner.invoke(cli, ["rooms", "--building", "home", "link", "kitchen", "hall", "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert (data["room_a"], data["room_b"]) == ("home/kitchen", "home/hall") and data["same_as"] == 5
    res = runner.invoke(cli, ["rooms", "--building", "home", "link", "kitchen", "hall", "--building", "other"])
    assert res.exit_code == 2
    assert len(res.output.strip().splitlines()) == 1 and "give --building once" in res.output
