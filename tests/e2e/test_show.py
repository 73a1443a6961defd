"""`sg3d show` on hand-made graphs in the real store: the top-down diagram (PNG, SVG, PDF) and the
plotly 3-D page. Expected positions come from the objects we made, not from the renderer."""
from __future__ import annotations

import itertools
import json
import re
import xml.etree.ElementTree as ET
from html.parser import HTMLParser

import cv2
import numpy as np
import pytest
from click.testing import CliRunner

from sg3d.cli import cli
from sg3d.core.stored import RoomFrame, Scene, StoredGraph, StoredObject, StoredRelation
from sg3d.graphdb.merge import merge_local_graph
from tests.factories import graph, obj
from tests.scenes import PLACES, UP, world
from tests.scenes import SHOW_BUILDING as BUILDING
from tests.scenes import SHOW_ROOM as ROOM
from tests.scenes import build_show_room as build
from tests.scenes import run_show as show

NS = "{http://www.w3.org/2000/svg}"


def svg_nodes(root) -> dict[str, np.ndarray]:
    """Node id -> marker centre (SVG units) from the diagram's node groups."""
    out = {}
    for g in root.iter(NS + "g"):
        gid = g.get("id") or ""
        if gid.startswith("node-"):
            use = next(g.iter(NS + "use"))
            out[gid[5:]] = np.array([float(use.get("x")), float(use.get("y"))])
    return out


def svg_scale(root) -> tuple[float, float]:
    """(metres, SVG units) of the scale bar: its path and its text."""
    bar = next(g for g in root.iter(NS + "g") if g.get("id") == "scalebar")
    xs = [float(v) for v in re.findall(r"([-\d.]+) [-\d.]+", next(bar.iter(NS + "path")).get("d"))]
    group = next(g for g in root.iter(NS + "g") if g.get("id") == "scalebar-label")
    label = "".join(next(group.iter(NS + "text")).itertext())
    assert re.fullmatch(r"[\d.]+ (m|cm)", label), label
    value = float(label.split()[0]) / (100 if label.endswith("cm") else 1)
    return value, max(xs) - min(xs)


def ids_by_label(store, room=ROOM):
    from sg3d.app.scene import fetch_scene

    return {n.label: n.id for n in fetch_scene(store, BUILDING, room).nodes}


def test_topdown_positions_are_the_objects_floor_positions(store, embedded_home, tmp_path):
    """Every distance between two nodes, in metres by the picture's own scale bar, is the floor
    distance between the objects as made (heights differ and the room's up is tilted)."""
    build(store)
    out = tmp_path / "g.svg"
    r = show(embedded_home, "--out", str(out))
    assert r.exit_code == 0, r.output
    root = ET.parse(out).getroot()
    pos = svg_nodes(root)
    metres, units = svg_scale(root)
    per_m = units / metres
    ids = ids_by_label(store)
    local = {"t": "dining table", "c": "cup", "b": "book", "h": "chair"}
    assert set(pos) == set(ids.values())
    for p, q in itertools.combinations(local, 2):
        drawn = np.linalg.norm(pos[ids[local[p]]] - pos[ids[local[q]]]) / per_m
        truth = np.hypot(PLACES[p][0] - PLACES[q][0], PLACES[p][1] - PLACES[q][1])
        assert drawn == pytest.approx(truth, abs=0.01), (p, q)


def test_png_size_painted_nodes_and_determinism(store, embedded_home, tmp_path):
    build(store)
    out, svg = tmp_path / "g.png", tmp_path / "g.svg"
    assert show(embedded_home, "--out", str(out), "--size", "900x700").exit_code == 0
    assert show(embedded_home, "--out", str(svg), "--size", "900x700").exit_code == 0
    img = cv2.imread(str(out))
    assert img is not None and img.shape == (700, 900, 3)
    # the SVG is the same figure in points (72 per inch, the PNG has 100 pixels per inch)
    for xy in svg_nodes(ET.parse(svg).getroot()).values():
        x, y = (int(round(v / 0.72)) for v in xy)
        assert (img[y - 1:y + 2, x - 1:x + 2] < 200).any(), (x, y)
    again = tmp_path / "g2.png"
    assert show(embedded_home, "--out", str(again), "--size", "900x700").exit_code == 0
    assert again.read_bytes() == out.read_bytes()
    pdf = tmp_path / "g.pdf"
    assert show(embedded_home, "--out", str(pdf)).exit_code == 0
    assert pdf.read_bytes().startswith(b"%PDF")


def test_labels_are_names_and_edges_one_merged_label_per_pair(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "g.svg"
    assert show(embedded_home, "--out", str(out)).exit_code == 0
    root = ET.parse(out).getroot()

    def texts(prefix):
        return sorted("".join(t.itertext()).replace("\n", " ") for g in root.iter(NS + "g")
                      if (g.get("id") or "").startswith(prefix) for t in g.iter(NS + "text"))

    assert texts("label-") == ["book", "chair", "cup", "dining table"]     # the names ask prints
    assert texts("edge-label-") == ["next to", "on", "on"]                 # size statements hidden
    page = ET.tostring(root, encoding="unicode")
    assert "o-" not in "".join(texts("label-")) and "4 size statements hidden" in page

    every = tmp_path / "all.svg"
    assert show(embedded_home, "--out", str(every), "--all-edges").exit_code == 0
    root = ET.parse(every).getroot()
    # each pair once: "cup on table" and "table bigger than cup" read from the cup's side
    assert texts("edge-label-") == ["next to / bigger than", "on", "on / smaller than"]


def test_many_crowded_objects_get_labels_that_never_overlap(store):
    """50 objects in 2 x 1.5 m: every node is named on the picture or numbered and listed, and
    no two texts on the map overlap (measured from the drawn figure's text extents)."""
    from sg3d.app.scene import fetch_scene
    from sg3d.render.diagram import draw

    rng = np.random.default_rng(3)
    labels = ["cup", "bowl", "bottle", "book", "chair", "vase", "laptop", "remote", "clock", "potted plant"]
    objs = [obj(f"o{i}", labels[i % len(labels)], world(rng.uniform(0, 2), rng.uniform(0, 1.5), 0.8),
                colour=["white", "red", "blue", "green", "black"][i % 5], frame=i) for i in range(50)]
    rels = [(f"o{i}", "NEXT_TO", f"o{i + 1}", 0.8) for i in range(0, 48, 3)]
    g = graph(objs, relations=rels, room="crowd", building=BUILDING)
    g.up = tuple(UP)
    merge_local_graph(store, g)
    scene = fetch_scene(store, BUILDING, "crowd")
    assert len(scene.nodes) == 50
    d = draw(scene, size=(1600, 1200))
    renderer = d.figure.canvas.get_renderer()
    ax_box = d.ax.get_window_extent(renderer)
    on_map = [t for t in d.ax.texts if t.get_text()]
    boxes = [t.get_window_extent(renderer) for t in on_map]
    for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2):
        assert not a.overlaps(b), (on_map[i].get_text(), on_map[j].get_text())
    for b in boxes:      # inside the map
        assert ax_box.x0 - 1 <= b.x0 and b.x1 <= ax_box.x1 + 1 and ax_box.y0 - 1 <= b.y0 and b.y1 <= ax_box.y1 + 1
    named = {t.get_gid()[6:] for t in on_map if (t.get_gid() or "").startswith("label-")}
    assert named == {n.id for n in scene.nodes}            # every node labelled (a name or a number)
    numbered = [t for t in on_map if (t.get_gid() or "").startswith("label-") and t.get_text().isdigit()]
    assert len(d.listed_nodes) >= len(numbered)
    assert sum(t.get_text().replace("\n", " ") in {n.name for n in scene.nodes} for t in on_map) >= 25


def test_building_outlines_and_names_its_rooms_in_the_building_frame(store, embedded_home, tmp_path):
    """Two rooms; the second's frame is the first's turned 90 degrees and moved 3 m. A chair made
    at one building position in both rooms is drawn at one point."""
    from sg3d.graphdb.building import set_room_transform
    from sg3d.graphdb.values import room_id

    build(store, room="kitchen")
    T = np.eye(4)
    T[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    T[:3, 3] = [3.0, 0.5, 0.0]
    # the hall's objects, made in the hall's frame: p_hall = T^-1 p_building
    inv = np.linalg.inv(T)
    chair_building = np.array(world(*PLACES["h"]))
    chair_hall = inv[:3, :3] @ chair_building + inv[:3, 3]
    g = graph([obj("x", "chair", tuple(chair_hall), colour="black"),
               obj("y", "couch", tuple(inv[:3, :3] @ np.array(world(1.0, 3.0, 0.4)) + inv[:3, 3]),
                   size=(2.0, 0.9, 0.8), colour="grey")], room="hall", building=BUILDING)
    g.up = tuple(inv[:3, :3] @ UP)
    merge_local_graph(store, g)
    set_room_transform(store, room_id(BUILDING, "kitchen"), np.eye(4))
    set_room_transform(store, room_id(BUILDING, "hall"), T)
    out = tmp_path / "b.svg"
    r = show(embedded_home, "--out", str(out), room=None)
    assert r.exit_code == 0, r.output
    root = ET.parse(out).getroot()
    texts = ["".join(t.itertext()) for t in root.iter(NS + "text")]
    assert "kitchen" in texts and "hall" in texts
    pos = svg_nodes(root)
    metres, units = svg_scale(root)
    from sg3d.app.scene import fetch_scene

    nodes = fetch_scene(store, BUILDING).nodes
    chairs = [n.id for n in nodes if n.label == "chair"]
    assert len(chairs) == 2
    assert np.linalg.norm(pos[chairs[0]] - pos[chairs[1]]) / (units / metres) < 0.01
    couch = next(n.id for n in nodes if n.label == "couch")
    table = next(n.id for n in nodes if n.label == "dining table")
    assert np.linalg.norm(pos[couch] - pos[table]) / (units / metres) == pytest.approx(np.hypot(1.0, 3.0), abs=0.01)


def test_spring_layout_with_all_edges_is_readable(store, embedded_home, tmp_path):
    """The promise of docs/commands.md (Pictures), checked on the SVG written: each connected
    group laid out on its own (groups never interleave), a hub between its neighbours, labels
    that never overlap, and size statements (--all-edges) that do not move anything."""
    from sg3d.app.scene import fetch_scene
    from sg3d.render.diagram import draw

    far = {**PLACES, "u": (4.0, 3.0, 0.4), "v": (4.5, 3.0, 0.9), "p": (-3.0, 2.0, 0.3)}
    g = graph([
        obj("t", "dining table", world(*far["t"]), size=(1.5, 0.8, 0.7), colour="brown"),
        obj("c", "cup", world(*far["c"]), colour="white"),
        obj("b", "book", world(*far["b"]), colour="red"),
        obj("h", "chair", world(*far["h"]), colour="black"),
        obj("u", "couch", world(*far["u"]), size=(2.0, 0.9, 0.8), colour="gray"),
        obj("v", "tv", world(*far["v"]), size=(1.0, 0.1, 0.6), colour="black"),
        obj("p", "potted plant", world(*far["p"]), colour="green"),
    ], relations=[("c", "ON", "t", 0.9), ("b", "ON", "t", 0.9), ("h", "NEXT_TO", "t", 0.8),
                  ("v", "NEXT_TO", "u", 0.8),
                  ("t", "BIGGER_THAN", "c", 0.9), ("u", "BIGGER_THAN", "t", 0.9), ("u", "BIGGER_THAN", "p", 0.9)],
        room=ROOM, building=BUILDING)
    g.up = tuple(UP)
    merge_local_graph(store, g)
    ids = ids_by_label(store)
    groups = [["dining table", "cup", "book", "chair"], ["couch", "tv"], ["potted plant"]]

    def positions(*extra):
        out = tmp_path / f"s{len(extra)}.svg"
        r = show(embedded_home, "--out", str(out), "--layout", "spring", *extra)
        assert r.exit_code == 0, r.output
        pos = svg_nodes(ET.parse(out).getroot())
        assert set(pos) == set(ids.values())
        return {label: pos[ids[label]] for label in ids}

    pos = positions("--all-edges")
    # size statements pull nothing: the same picture positions without them
    without = positions()
    assert all(np.allclose(pos[k], without[k], atol=0.5) for k in pos)
    # groups are laid out apart: their bounding boxes (+ a marker) never overlap
    boxes = [(np.min([pos[k] for k in grp], axis=0) - 5, np.max([pos[k] for k in grp], axis=0) + 5) for grp in groups]
    for (lo1, hi1), (lo2, hi2) in itertools.combinations(boxes, 2):
        assert np.any(hi1 < lo2) or np.any(hi2 < lo1), "two connected groups interleave"
    # the table holds the star together: of its group, it is every leaf's nearest node, and
    # nearer to the group's centre than any leaf
    star = groups[0]
    for leaf in star[1:]:
        assert min((k for k in star if k != leaf), key=lambda k: np.linalg.norm(pos[k] - pos[leaf])) == "dining table"
    centre = np.mean([pos[k] for k in star], axis=0)
    assert min(star, key=lambda k: np.linalg.norm(pos[k] - centre)) == "dining table"
    # nodes spread out, labels readable
    assert min(np.linalg.norm(pos[p] - pos[q]) for p, q in itertools.combinations(pos, 2)) > 10
    d = draw(fetch_scene(store, BUILDING, ROOM), layout="spring", all_edges=True)
    renderer = d.figure.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in d.ax.texts if t.get_text()]
    assert len(boxes) >= 7
    assert not any(a.overlaps(b) for a, b in itertools.combinations(boxes, 2))


class Tags(HTMLParser):
    """Every tag's attributes, and whether open tags close (html.parser is lenient)."""

    def __init__(self):
        super().__init__()
        self.stack, self.attrs = [], []

    def handle_starttag(self, tag, attrs):
        self.attrs.append((tag, dict(attrs)))
        if tag not in ("meta", "input", "br", "link"):
            self.stack.append(tag)

    def handle_endtag(self, tag):
        assert self.stack.pop() == tag


def test_html_is_self_contained_plotly_with_names_and_toggled_relations(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "g.html"
    assert show(embedded_home, "--out", str(out)).exit_code == 0
    page = out.read_text()
    p = Tags()
    p.feed(page)
    assert p.stack == []
    # nothing is loaded from elsewhere: no src/href to another host, plotly.js inline
    for tag, attrs in p.attrs:
        for k in ("src", "href"):
            assert not re.match(r"(https?:)?//", attrs.get(k) or ""), (tag, attrs)
    assert "Plotly.newPlot" in page and len(page) > 1_000_000
    spec = json.loads(re.search(r'Plotly\.newPlot\(\s*"sg3d-view",\s*(\[.*?\]),\s*\{"template"', page, re.S).group(1))
    names = next(t for t in spec if t.get("name") == "names")
    assert sorted(names["text"]) == ["book", "chair", "cup", "dining table"]
    rel = {t["name"]: t.get("visible", True) for t in spec if t.get("mode") == "lines" and "(" in t["name"]}
    assert rel["on (2)"] is True and rel["next to (1)"] is True
    assert rel["bigger than (2)"] == "legendonly" and rel["smaller than (2)"] == "legendonly"
    # one legend entry per relation type, in the second legend, each type its own colour (its
    # hover points too), every other trace in the first legend
    lines = [t for t in spec if t.get("mode") == "lines" and "(" in t.get("name", "")]
    assert sorted(t["name"] for t in lines) == sorted(rel) and all(t["legend"] == "legend2" for t in lines)
    colours = {t["name"]: t["line"]["color"] for t in lines}
    assert len(set(colours.values())) == len(colours), colours
    for t in spec:
        if (t.get("legendgroup") or "").startswith("rel-") and t.get("mode") == "markers":
            assert t["legend"] == "legend2" and t.get("showlegend") is False
            assert t["marker"]["color"] == next(c for n, c in colours.items() if n.startswith(t["name"] + " ("))
    assert not [t for t in spec if not (t.get("legendgroup") or "").startswith("rel-") and t.get("legend")
                not in (None, "legend")]
    # the layout as written: axes titled in metres, the two legends' titles
    layout = plotly_layout(page)
    assert [layout["scene"][a]["title"]["text"] for a in ("xaxis", "yaxis", "zaxis")] == ["x (m)", "y (m)", "up (m)"]
    assert layout["legend"]["title"]["text"].startswith("<b>objects</b>")
    assert layout["legend2"]["title"]["text"].startswith("<b>relations</b>")


def plotly_layout(page: str) -> dict:
    """The layout object of the page's Plotly.newPlot call (the argument after the data)."""
    dec = json.JSONDecoder()
    start = re.search(r'Plotly\.newPlot\(\s*"sg3d-view",\s*', page).end()
    _, end = dec.raw_decode(page, start)
    return dec.raw_decode(page, page.index("{", end))[0]


def made_scene(nodes: list[tuple], edges=()) -> Scene:
    """A scene as sg3d.app.scene.fetch_scene returns it, from (id, label, layer, name, (x, y, z),
    (w, d, h)) tuples in a room whose up is z."""
    stored = StoredGraph("b", "r",
                         [StoredObject(id=i, label=label, layer=layer, name=name, room_name="r", colour="white",
                                       x=p[0], y=p[1], z=p[2], box_centre=list(p), size=list(size))
                          for i, label, layer, name, p, size in nodes],
                         [StoredRelation(a, t, b, 0.9) for a, t, b in edges])
    return Scene(stored, {"r": RoomFrame("b/r", [0, 0, 1], None)})


def test_html_names_named_objects_on_the_page_others_on_demand_never_overlapping():
    """Walls, the floor and unnamed objects are named on hover and in a legend-only trace; the
    named objects' names are on the page, and eight cups crowded on one table get names that
    do not overlap in the first view (raised over their cups, each joined by a leader)."""
    from sg3d.render.view3d import figure, screen_boxes, stack_names

    walls = [(f"w{k}", "wall", "structure", f"wall {k}", (k * 1.2, 3.0, 1.2), (1.2, 0.1, 2.4)) for k in range(4)]
    unnamed = [(f"u{k}", "object", "object", f"white object {k}", (k * 1.2, 2.8, 0.5), (0.4, 0.3, 0.5))
               for k in range(4)]
    cups = [(f"c{k}", "cup", "object", f"white cup {k}", (1.5 + 0.06 * k, 1.0 + 0.02 * k, 0.8), (0.08, 0.08, 0.1))
            for k in range(8)]
    table = [("t", "dining table", "object", "dining table", (1.7, 1.1, 0.375), (1.6, 0.9, 0.75)),
             ("f", "floor", "structure", "floor", (2.0, 1.5, 0.0), (4.5, 3.2, 0.01))]
    scene = made_scene(walls + unnamed + cups + table, [(f"c{k}", "ON", "t") for k in range(8)])
    fig = figure(scene)
    by_name = {t.name: t for t in fig.data}
    names, others = by_name["names"], by_name["other names"]
    assert sorted(names.text) == sorted(["dining table"] + [f"white cup {k}" for k in range(8)])
    assert names.visible is True and others.visible == "legendonly"
    assert sorted(others.text) == sorted([n[3] for n in walls + unnamed] + ["floor"])
    # every box still names its object on hover
    hovered = {re.search(r"<b>(.*?)</b>", h).group(1) for t in fig.data if t.type == "mesh3d" for h in t.hovertext}
    assert hovered == {n.name for n in scene.nodes}
    scn = fig.layout.scene
    lo = np.array([scn.xaxis.range[0], scn.yaxis.range[0], scn.zaxis.range[0]])
    hi = np.array([scn.xaxis.range[1], scn.yaxis.range[1], scn.zaxis.range[1]])
    mid, span = (lo + hi) / 2, float((hi - lo).max())
    spots = np.stack([names.x, names.y, names.z], axis=1)
    boxes = screen_boxes(spots, list(names.text), mid, span)
    assert not [(names.text[i], names.text[j]) for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2)
                if a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]]
    # names stay over their objects: only raised, and the raised ones have leaders
    centre = {n.name: n.box_centre for n in scene.nodes}
    top = {n.name: n.box_centre[2] + n.size[2] / 2 for n in scene.nodes}
    for text, p in zip(names.text, spots):
        if text != "dining table":                   # a large object is named at its corner
            assert p[:2] == pytest.approx(centre[text][:2])
        assert p[2] >= top[text]
    raised = sum(p[2] > top[t] + 0.1 for t, p in zip(names.text, spots))
    assert raised >= 4 and len(by_name["names leaders"].x) == 3 * raised
    # placing names that never collide changes nothing
    apart = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]])
    assert np.array_equal(stack_names(apart, ["a", "b"], np.zeros(3), 5.0), apart)


def test_html_boxes_are_the_objects_boxes(store):
    """The drawn box of each object spans its size (w, d, h) and the boxes' centres are as far
    apart on the floor and in height as the objects made."""
    from sg3d.app.scene import fetch_scene
    from sg3d.render.view3d import figure

    build(store)
    scene = fetch_scene(store, BUILDING, ROOM)
    fig = figure(scene)
    made = {"dining table": (1.5, 0.8, 0.7), "cup": (0.1, 0.1, 0.1), "book": (0.1, 0.1, 0.1), "chair": (0.1, 0.1, 0.1)}
    centres = {}
    for t in fig.data:
        if t.type != "mesh3d":
            continue
        xyz = np.stack([np.asarray(t.x), np.asarray(t.y), np.asarray(t.z)], axis=1).reshape(-1, 8, 3)
        for box, text in zip(xyz, np.asarray(t.hovertext).reshape(-1, 8)[:, 0]):
            name = re.search(r"<b>(.*?)</b>", text).group(1)
            ext = box.max(axis=0) - box.min(axis=0)
            assert ext[2] == pytest.approx(made[name][2], abs=1e-6), name       # height along up
            assert sorted(ext[:2]) == pytest.approx(sorted(made[name][:2]), abs=1e-6), name
            centres[name] = box.mean(axis=0)
    assert set(centres) == set(made)
    local = {"dining table": "t", "cup": "c", "book": "b", "chair": "h"}
    for p, q in itertools.combinations(centres, 2):
        P, Q = np.array(PLACES[local[p]]), np.array(PLACES[local[q]])
        assert np.hypot(*(centres[p] - centres[q])[:2]) == pytest.approx(np.hypot(*(P - Q)[:2]), abs=1e-6)
        assert (centres[p] - centres[q])[2] == pytest.approx((P - Q)[2], abs=1e-6)


def test_point_cloud_from_the_real_kitchen(kitchen_dir):
    from sg3d.app.scene import VOXEL_M, sequence_cloud

    P, C = sequence_cloud(kitchen_dir, frames=2, max_points=3000)
    assert 1000 <= len(P) <= 3000 and P.shape == (len(P), 3) and C.shape == (len(P), 3)
    assert np.isfinite(P).all() and C.dtype == np.uint8 and C.std() > 10      # real colours, not one grey
    # one point per centimetre cube: the overlapping frames' repeats are gone
    cells = np.floor(P / VOXEL_M).astype(np.int64)
    assert len(np.unique(cells, axis=0)) == len(P)
    # the room, not a speck: the kitchen's depth spans metres
    assert (P.max(axis=0) - P.min(axis=0)).max() > 1.5


@pytest.mark.parametrize("name", ["g.jpg", "g", "g.gif"])
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


def test_real_kitchen_png_has_scale_bar_legend_and_labels_that_never_overlap(store, embedded_home, kitchen_dir,
                                                                            tmp_path):
    """The first half of the real kitchen, built by `sg3d build`, drawn as `sg3d show` draws it."""
    from sg3d.app.scene import fetch_scene
    from sg3d.queries.taxonomy import Taxonomy
    from sg3d.render.diagram import draw

    r = CliRunner().invoke(cli, ["--home", str(embedded_home), "build", str(kitchen_dir), "--room", "kitchen",
                                 "--building", BUILDING, "--stop", "500", "--json"])
    assert r.exit_code == 0, r.output
    out, svg = tmp_path / "k.png", tmp_path / "k.svg"
    for f in (out, svg):
        r = show(embedded_home, "--out", str(f), room="kitchen")
        assert r.exit_code == 0, r.output
    scene = fetch_scene(store, BUILDING, "kitchen")
    assert len(scene.nodes) >= 4
    img = cv2.imread(str(out))
    assert img.shape == (1200, 1600, 3)
    # the scale bar: a black bar at least 50 px long in the right-hand column, labelled in the SVG
    panel = img[:, 1150:]
    runs = [(row < 60).all(axis=-1).sum() for row in panel]
    assert max(runs) >= 50
    root = ET.parse(svg).getroot()
    metres, units = svg_scale(root)
    assert metres > 0 and units / 0.72 >= 50
    # the legend names each object's category
    texts = {"".join(t.itertext()) for t in root.iter(NS + "text")}
    tax = Taxonomy.load()
    for n in scene.nodes:
        assert (tax.parent(n.label) or n.label) in texts, n.label
    # labels: every node named (or numbered) on the map, no two texts overlapping
    d = draw(scene, title="default/kitchen")
    renderer = d.figure.canvas.get_renderer()
    on_map = [t for t in d.ax.texts if t.get_text()]
    boxes = [t.get_window_extent(renderer) for t in on_map]
    assert not [(on_map[i].get_text(), on_map[j].get_text())
                for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2) if a.overlaps(b)]
    assert {t.get_gid()[6:] for t in on_map if (t.get_gid() or "").startswith("label-")} == \
        {n.id for n in scene.nodes}


def test_what_show_wrote_is_its_result_on_stdout(store, embedded_home, tmp_path):
    build(store)
    out = tmp_path / "room.svg"
    r = show(embedded_home, "--out", str(out))
    assert r.exit_code == 0, r.output
    assert r.stdout.startswith(f"wrote {out} (") and out.is_file(), (r.stdout, r.stderr)
    assert "wrote" not in r.stderr
