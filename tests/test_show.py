"""`sg3d show` on hand-made graphs in the real store: PNG, SVG and HTML pictures."""
from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET

import cv2
import numpy as np
import pytest
from click.testing import CliRunner

from graphdb.merge import merge_local_graph
from queries.render import drawn_edges, load_scene, make_layout
from sg3d.cli import cli
from tests.factories import graph, obj

ROOM, BUILDING = "showroom", "home"


def build(store):
    """A table with a cup and a book on it, a chair beside it: 4 nodes, 2 ON + 1 NEXT_TO edges and
    comparison edges that the default picture hides."""
    merge_local_graph(store, graph([
        obj("t", "dining table", (0.0, 0.0, 0.0), size=(1.5, 0.8, 0.7), colour="brown"),
        obj("c", "cup", (0.2, 0.1, 0.4), colour="white"),
        obj("b", "book", (-0.4, -0.2, 0.4), colour="red"),
        obj("h", "chair", (1.4, 0.0, 0.0), colour="black"),
    ], relations=[("c", "ON", "t", 0.9), ("b", "ON", "t", 0.9), ("h", "NEXT_TO", "t", 0.8),
                  ("t", "BIGGER_THAN", "c", 0.9), ("t", "BIGGER_THAN", "h", 0.9)],
        room=ROOM, building=BUILDING))


def show(home, *args):
    return CliRunner().invoke(cli, ["--home", str(home), "show", "--room", ROOM, "--building", BUILDING, *args])


def test_png_is_an_image_of_the_requested_size_with_nodes_drawn(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "g.png"
    r = show(embedded_home, "--out", str(out), "--size", "900x700")
    assert r.exit_code == 0, r.output
    img = cv2.imread(str(out))
    assert img is not None and img.shape == (700, 900, 3)
    # every node's centre, recomputed with the same deterministic layout, is painted (not white)
    scene = load_scene(store, BUILDING, ROOM)
    lay = make_layout(scene, 900, 700, "topdown", scene.edges)
    assert len(lay.pos) == 4
    for p in lay.pos.values():
        x, y = (int(round(v)) for v in p)
        assert (img[y, x] < 200).any(), (x, y, img[y, x])
    # topdown keeps the floor arrangement: the chair (x = 1.4) is right of the book (x = -0.4)
    by_label = {n["label"]: n["id"] for n in scene.nodes}
    assert lay.pos[by_label["chair"]][0] > lay.pos[by_label["book"]][0]
    # deterministic: the same store draws the same picture
    again = tmp_path / "g2.png"
    assert show(embedded_home, "--out", str(again), "--size", "900x700").exit_code == 0
    assert again.read_bytes() == out.read_bytes()


def test_spring_layout_png(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "s.png"
    r = show(embedded_home, "--out", str(out), "--layout", "spring")
    assert r.exit_code == 0, r.output
    assert cv2.imread(str(out)).shape == (1200, 1600, 3)


def test_svg_has_one_node_group_per_node_and_a_label_per_edge(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "g.svg"
    assert show(embedded_home, "--out", str(out)).exit_code == 0
    root = ET.parse(out).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    groups = [g for g in root.iter(ns + "g") if g.get("class") == "node"]
    assert len(groups) == 4
    assert all(len(g.findall(ns + "circle")) == 1 for g in groups)
    text = " ".join("".join(t.itertext()) for g in groups for t in g.iter(ns + "text"))
    for name in ("dining table", "cup", "book", "chair"):    # the names ask prints (one of each label)
        assert name in text
    assert "#" not in text and "o-" not in text
    labels = [t.text for t in root.iter(ns + "text") if t.get("class") == "edge-label"]
    lines = [e for e in root.iter(ns + "line") if e.get("class") == "edge"]
    assert sorted(labels) == ["NEXT_TO", "ON", "ON"] and len(lines) == 3     # comparisons hidden
    # a size statement is stored as BIGGER_THAN with its SMALLER_THAN (ingest.relation_rules)
    assert "4 comparison edges hidden" in ET.tostring(root, encoding="unicode")

    every = tmp_path / "all.svg"
    assert show(embedded_home, "--out", str(every), "--all-edges").exit_code == 0
    labels = [t.text for t in ET.parse(every).getroot().iter(ns + "text") if t.get("class") == "edge-label"]
    # NEXT_TO is stored from the smaller id, so it may share one line with table BIGGER_THAN chair
    assert sorted(t for label in labels for t in label.split(", ")) == ["BIGGER_THAN", "BIGGER_THAN", "NEXT_TO", "ON", "ON"]


def test_html_is_self_contained_and_holds_the_labels(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "g.html"
    assert show(embedded_home, "--out", str(out)).exit_code == 0
    page = out.read_text()
    assert "<canvas" in page and "http://" not in page and "https://" not in page and "src=" not in page
    data = json.loads(re.search(r'<script type="application/json" id="data">(.*?)</script>', page, re.S).group(1))
    assert sorted(b["name"] for b in data["boxes"]) == \
        ["book", "chair", "cup", "dining table"]
    # 2 ON + 1 NEXT_TO + 2 size statements, each stored as BIGGER_THAN with its SMALLER_THAN
    assert len(data["edges"]) == 7 and data["cmp"] is False and data["points"] == []
    # the page parses as markup (html.parser is lenient; check the elements are balanced)
    from html.parser import HTMLParser

    class Tags(HTMLParser):
        def __init__(self):
            super().__init__()
            self.stack = []

        def handle_starttag(self, tag, attrs):
            if tag not in ("meta", "input", "br"):
                self.stack.append(tag)

        def handle_endtag(self, tag):
            assert self.stack.pop() == tag

    p = Tags()
    p.feed(page)
    assert p.stack == []


def test_html_point_cloud_from_the_real_kitchen(store, embedded_home, tmp_path, kitchen_dir):
    build(store)
    out = tmp_path / "cloud.html"
    r = show(embedded_home, "--out", str(out), "--sequence", str(kitchen_dir), "--frames", "2",
             "--max-points", "3000")
    assert r.exit_code == 0, r.output
    data = json.loads(re.search(r'id="data">(.*?)</script>', out.read_text(), re.S).group(1))
    pts = np.array(data["points"])
    assert 1000 <= len(pts) <= 3000 and pts.shape[1] == 6
    assert np.isfinite(pts).all() and ((pts[:, 3:] >= 0) & (pts[:, 3:] <= 255)).all()


def test_inverse_edges_are_drawn_once():
    edges = [{"s": "a", "type": "IN_FRONT_OF", "o": "b"}, {"s": "b", "type": "BEHIND", "o": "a"},
             {"s": "a", "type": "NEAR", "o": "b"}, {"s": "b", "type": "NEAR", "o": "a"},
             {"s": "c", "type": "UNDER", "o": "a"}]
    got = [(e.s, e.o, e.types, e.both) for e in drawn_edges(edges)]
    assert got == [("a", "b", ["NEAR"], True), ("a", "b", ["IN_FRONT_OF"], False), ("c", "a", ["UNDER"], False)]


@pytest.mark.parametrize("name", ["g.jpg", "g", "g.pdf"])
def test_bad_out_suffix_is_one_line_exit_2(embedded_home, tmp_path, name):
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-m", "sg3d", "--home", str(embedded_home), "show",
                           "--out", str(tmp_path / name)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and ".png" in proc.stderr
    assert not (tmp_path / name).exists()


def test_empty_room_is_an_error(store, embedded_home, tmp_path):
    r = show(embedded_home, "--out", str(tmp_path / "x.png"))
    assert r.exit_code == 2 and "nothing to show" in r.output
