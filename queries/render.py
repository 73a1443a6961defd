"""Pictures of a stored scene graph (`sg3d show`, `sg3d eval --report`).

Three outputs from one layout:
- PNG (OpenCV) and SVG (written by hand): a node-link diagram. Nodes sit at their top-down floor
  position (the object's mean projected onto the plane perpendicular to the room's up, in the
  same (e1, e2, up) frame the sizes are measured in) or at a seeded Fruchterman-Reingold layout;
  then an overlap relaxation moves nodes apart until no two label boxes overlap, because with
  ~50 objects in a kitchen several share a shelf and would print over each other.
- HTML: a self-contained 3-D view (canvas + inline JS, no network) of labelled wireframe boxes,
  relation lines and, optionally, a subsampled point cloud of a few frames.

Comparison edges (BIGGER_THAN / SMALLER_THAN) connect nearly every pair of objects and bury
the spatial relations, so they are hidden unless asked for.
"""
from __future__ import annotations

import hashlib
import html
import json
from dataclasses import dataclass, field
from typing import Iterable, Optional, Sequence

import cv2
import numpy as np

from ingest.relations import horizontal_basis

COMPARISON_TYPES = frozenset({"BIGGER_THAN", "SMALLER_THAN"})
LAYOUTS = ("topdown", "spring")

# 20 well-separated colours (RGB); a taxonomy group keeps its colour across pictures because the
# index comes from the sorted group names of the fixed taxonomy, not from what a room holds.
PALETTE = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
           (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207),
           (174, 199, 232), (255, 187, 120), (152, 223, 138), (255, 152, 150), (197, 176, 213),
           (196, 156, 148), (247, 182, 210), (199, 199, 199), (219, 219, 141), (158, 218, 229)]
# Evaluation status -> fill colour (RGB).
STATUS_COLOURS = {"matched": (46, 170, 70), "spurious": (220, 40, 40), "duplicate": (255, 150, 0)}
MISSING_COLOUR = (200, 0, 0)
BACKGROUND = (255, 255, 255)
LEGEND_W = 230          # right-hand column kept free of nodes for the legend
MARGIN = 40
NODE_R = 9
FONT = cv2.FONT_HERSHEY_SIMPLEX
FONT_SCALE = 0.42
EDGE_FONT_SCALE = 0.36


# --------------------------------------------------------------------------- data


@dataclass
class Scene:
    """What a picture needs: the nodes and edges of fetch_graph and each room's up direction."""
    nodes: list[dict]
    edges: list[dict]
    ups: dict[str, Optional[tuple[float, float, float]]] = field(default_factory=dict)


def load_scene(store, building: str, room: Optional[str] = None) -> Scene:
    from graphdb.export import fetch_graph

    graph = fetch_graph(store, building, room)
    ups = {r["room"]: (tuple(r["up"]) if r.get("up") else None)
           for r in store.read("show_rooms", building=building, room=room)}
    return Scene(graph["nodes"], graph["edges"], ups)


def room_up(scene: Scene, room: str) -> np.ndarray:
    """The stored up of a room; without one (a graph merged without depth), the direction in
    which the object centres vary least: rooms are wider than they are tall."""
    up = scene.ups.get(room)
    if up is not None:
        return np.asarray(up, dtype=np.float64)
    pts = np.array([[n["x"], n["y"], n["z"]] for n in scene.nodes
                    if n.get("room_name") == room and n.get("x") is not None], dtype=np.float64)
    if len(pts) < 3:
        return np.array([0.0, 0.0, 1.0])
    _, _, vt = np.linalg.svd(pts - pts.mean(axis=0))
    return vt[2]


def display_names(nodes: Sequence[dict], edges: Iterable[dict] = ()) -> dict[str, str]:
    """id -> the readable name ask and plan use (queries/naming.py: "white cup", "chair 2",
    "red cup on the dining table"); `edges` ({s, type, o, score}) give what each stands on."""
    from queries.naming import name_graph

    graph = name_graph({"nodes": [dict(n) for n in nodes], "edges": list(edges)})
    return {n["id"]: n["name"] for n in graph["nodes"]}


def category_of(label: str) -> str:
    """The label's taxonomy group (its parent), or the label itself outside the taxonomy."""
    try:
        from queries.taxonomy import Taxonomy

        return Taxonomy.load().parent(label) or label
    except Exception:  # noqa: BLE001 - a missing taxonomy only costs colour grouping
        return label


def category_colour(group: str) -> tuple[int, int, int]:
    try:
        from queries.taxonomy import Taxonomy

        groups = sorted(Taxonomy.load().groups)
    except Exception:  # noqa: BLE001
        groups = []
    if group in groups:
        return PALETTE[groups.index(group) % len(PALETTE)]
    # not a group: a stable hash, so one label always gets one colour
    return PALETTE[int(hashlib.sha1(group.encode()).hexdigest(), 16) % len(PALETTE)]


def visible_edges(edges: Iterable[dict], all_edges: bool) -> list[dict]:
    return [e for e in edges if all_edges or e["type"] not in COMPARISON_TYPES]


# --------------------------------------------------------------------------- layout


def topdown_coords(scene: Scene) -> dict[str, np.ndarray]:
    """id -> (a, b) metres on the floor plane of its room; rooms side by side (each room is in
    its own sequence's world frame, so their coordinates cannot share one plot)."""
    out: dict[str, np.ndarray] = {}
    offset = 0.0
    for room in sorted({n.get("room_name") or "" for n in scene.nodes}):
        e1, e2, _ = horizontal_basis(room_up(scene, room))
        ids, pts = [], []
        for n in scene.nodes:
            if (n.get("room_name") or "") == room:
                ids.append(n["id"])
                p = np.array([n.get("x") or 0.0, n.get("y") or 0.0, n.get("z") or 0.0])
                pts.append((p @ e1, p @ e2))
        if not pts:
            continue
        xy = np.array(pts)
        xy[:, 0] += offset - xy[:, 0].min()
        offset = xy[:, 0].max() + 1.5
        out.update(zip(ids, xy))
    return out


def project_points(points: np.ndarray, up: Sequence[float]) -> np.ndarray:
    """World points (N x 3) -> floor coordinates (N x 2) in the frame of topdown_coords."""
    e1, e2, _ = horizontal_basis(up)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return np.stack([p @ e1, p @ e2], axis=1)


def spring_coords(ids: Sequence[str], edges: Iterable[dict], seed: int = 0, iterations: int = 300) -> dict[str, np.ndarray]:
    """Fruchterman-Reingold in NumPy with a fixed seed: the same graph gives the same picture."""
    n = len(ids)
    if n == 0:
        return {}
    index = {k: i for i, k in enumerate(ids)}
    pos = np.random.default_rng(seed).uniform(-1, 1, size=(n, 2))
    adj = np.zeros((n, n))
    for e in edges:
        if e["s"] in index and e["o"] in index and e["s"] != e["o"]:
            adj[index[e["s"]], index[e["o"]]] = adj[index[e["o"]], index[e["s"]]] = 1.0
    k = np.sqrt(4.0 / n)
    temp = 0.2
    for _ in range(iterations):
        delta = pos[:, None, :] - pos[None, :, :]
        dist = np.maximum(np.linalg.norm(delta, axis=-1), 1e-3)
        force = (k * k / dist ** 2 - adj * dist / k)          # repulsion minus attraction, / dist
        np.fill_diagonal(force, 0.0)
        # weak pull to the centre: without it a node with no edge drifts off and squeezes the rest
        disp = (delta * force[..., None]).sum(axis=1) - pos * (2.0 * k)
        length = np.maximum(np.linalg.norm(disp, axis=1), 1e-9)
        pos += disp / length[:, None] * np.minimum(length, temp)[:, None]
        temp = max(temp * 0.985, 0.002)
    return dict(zip(ids, pos))


def text_size(text: str, scale: float = FONT_SCALE) -> tuple[int, int]:
    (w, h), base = cv2.getTextSize(text, FONT, scale, 1)
    return w, h + base


@dataclass
class Layout:
    width: int
    height: int
    pos: dict[str, np.ndarray]            # node id -> pixel centre
    scale: float                          # pixels per metre (topdown), 0 for spring
    to_pixels: object = None              # floor coords (N x 2) -> pixels, topdown only
    boxes: dict = field(default_factory=dict)   # node id -> label box (x0, y0, x1, y1), circle included


def relax(pos: np.ndarray, half: np.ndarray, offset: np.ndarray, lo: np.ndarray, hi: np.ndarray,
          iterations: int = 400) -> np.ndarray:
    """Push overlapping label boxes apart (box i: centre pos[i] + offset[i], half-size half[i]).

    Each round, every overlapping pair moves apart along the axis of smaller overlap by half
    that overlap each: the least movement that separates them, so nodes stay near their floor
    position. Boxes are clamped to [lo, hi] (pixel bounds of node centres)."""
    p = pos.astype(np.float64).copy()
    n = len(p)
    if n < 2:
        return np.clip(p, lo, hi)
    pad = 14.0       # breathing room between labels, so edges between close nodes stay visible
    for _ in range(iterations):
        c = p + offset
        d = c[:, None, :] - c[None, :, :]
        over = (half[:, None, :] + half[None, :, :] + pad) - np.abs(d)
        mask = (over > 0).all(axis=-1)
        np.fill_diagonal(mask, False)
        if not mask.any():
            break
        axis_x = over[..., 0] < over[..., 1]
        push = np.zeros_like(d)
        sign = np.where(d == 0, 1.0, np.sign(d))
        # identical centres: break the tie by index so the pair still separates
        tie = np.sign(np.arange(n)[:, None] - np.arange(n)[None, :]).astype(np.float64)
        sign = np.where(d == 0, tie[..., None], sign)
        push[..., 0] = np.where(mask & axis_x, over[..., 0] * 0.5 * sign[..., 0], 0.0)
        push[..., 1] = np.where(mask & ~axis_x, over[..., 1] * 0.5 * sign[..., 1], 0.0)
        p += push.sum(axis=1) * 0.5
        p = np.clip(p, lo, hi)
    return p


def label_lines(name: str) -> list[str]:
    """A long name on two lines ("red cup", "on the dining table"): narrower boxes overlap less."""
    for sep in (" on the ", " in the "):
        if sep in name:
            head, tail = name.split(sep, 1)
            return [head, sep.strip() + " " + tail]
    return [name]


def make_layout(scene: Scene, width: int, height: int, layout: str = "topdown",
                edges: Optional[list[dict]] = None, extra_points: Optional[np.ndarray] = None) -> Layout:
    """Pixel positions of every node. `extra_points`: floor coordinates (topdown) that must also
    fit the picture (missing GT objects in a report)."""
    ids = [n["id"] for n in scene.nodes]
    names = display_names(scene.nodes, scene.edges)
    area_lo = np.array([MARGIN, MARGIN], dtype=np.float64)
    area_hi = np.array([width - LEGEND_W - MARGIN, height - MARGIN], dtype=np.float64)
    area_hi = np.maximum(area_hi, area_lo + 1)
    if layout == "topdown":
        coords = topdown_coords(scene)
    else:
        coords = spring_coords(ids, edges or [])
    raw = np.array([coords[i] for i in ids]) if ids else np.zeros((0, 2))
    allpts = raw if extra_points is None or len(extra_points) == 0 else np.vstack([raw, extra_points])
    if len(allpts):
        mn, mx = allpts.min(axis=0), allpts.max(axis=0)
    else:
        mn, mx = np.zeros(2), np.ones(2)
    span = np.maximum(mx - mn, 1e-6)
    scale = float(min((area_hi - area_lo) / span))
    centre_px = (area_lo + area_hi) / 2
    centre_w = (mn + mx) / 2

    def to_pixels(xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        # image y grows downwards; flip b so (e1, e2) looks like a map seen from above
        return np.stack([centre_px[0] + (xy[:, 0] - centre_w[0]) * scale,
                         centre_px[1] - (xy[:, 1] - centre_w[1]) * scale], axis=1)

    px = to_pixels(raw) if len(raw) else raw
    # label box: circle above, text lines centred below it
    half, offset = [], []
    for i in ids:
        lines = label_lines(names[i])
        w = max(text_size(t)[0] for t in lines)
        h = NODE_R * 2 + 4 + sum(text_size(t)[1] + 2 for t in lines)
        half.append((max(w, 2 * NODE_R) / 2, h / 2))
        offset.append((0.0, h / 2 - NODE_R))
    if len(px):
        px = relax(px, np.array(half), np.array(offset), area_lo, area_hi)
    boxes = {i: (p[0] - hw, p[1] + off - hh, p[0] + hw, p[1] + off + hh)
             for i, p, (hw, hh), (_, off) in zip(ids, px, half, offset)}
    return Layout(width, height, dict(zip(ids, px)), scale if layout == "topdown" else 0.0,
                  to_pixels if layout == "topdown" else None, boxes)


# --------------------------------------------------------------------------- drawing model


@dataclass
class DrawnEdge:
    s: str
    o: str
    types: list[str]
    both: bool          # arrowheads at both ends: the same types point both ways
    shift: float        # perpendicular offset in pixels, so opposite edges of a pair do not coincide


# b -INVERSE-> a restates a -CANONICAL-> b; drawn only when that canonical edge is absent.
INVERSE_OF = {"BEHIND": "IN_FRONT_OF", "BELOW": "ABOVE", "UNDER": "ON", "RIGHT_OF": "LEFT_OF",
              "SMALLER_THAN": "BIGGER_THAN", "CONTAINS_OBJ": "IN"}


def drawn_edges(edges: Iterable[dict]) -> list[DrawnEdge]:
    """One drawn line per pair and direction, its types joined: a pair holding ON and ABOVE gets
    one line labelled "ABOVE, ON"; NEXT_TO both ways gets one double-headed line; "b BEHIND a"
    is left out when "a IN_FRONT_OF b" is there (the relation extractor emits both)."""
    edges = list(edges)
    present = {(e["s"], e["type"], e["o"]) for e in edges}
    by_pair: dict[tuple[str, str], dict[str, set]] = {}
    for e in edges:
        if e["s"] == e["o"]:
            continue
        canon = INVERSE_OF.get(e["type"])
        if canon is not None and (e["o"], canon, e["s"]) in present:
            continue
        a, b = sorted((e["s"], e["o"]))
        d = by_pair.setdefault((a, b), {"fwd": set(), "bwd": set()})
        d["fwd" if e["s"] == a else "bwd"].add(e["type"])
    out = []
    for (a, b), d in sorted(by_pair.items()):
        common = d["fwd"] & d["bwd"]
        fwd, bwd = d["fwd"] - common, d["bwd"] - common
        parts = [(a, b, sorted(common), True), (a, b, sorted(fwd), False), (b, a, sorted(bwd), False)]
        parts = [p for p in parts if p[2]]
        shifts = [0.0] if len(parts) == 1 else [-7.0, 7.0] if len(parts) == 2 else [-10.0, 0.0, 10.0]
        for (s, o, types, both), shift in zip(parts, shifts):
            out.append(DrawnEdge(s, o, types, both, shift))
    return out


def _edge_geometry(layout: Layout, e: DrawnEdge):
    """Endpoints on the circles' borders (shifted sideways for parallel edges) and label point."""
    p, q = layout.pos[e.s], layout.pos[e.o]
    d = q - p
    length = float(np.linalg.norm(d))
    if length < 1e-6:
        return None
    u = d / length
    nrm = np.array([-u[1], u[0]])
    # shift measured in the pair's canonical direction, so opposite edges land on opposite sides
    sign = 1.0 if e.s < e.o else -1.0
    off = nrm * e.shift * sign
    a = p + u * (NODE_R + 2) + off
    b = q - u * (NODE_R + 2) + off
    mid = (a + b) / 2 + off * 0.8
    return a, b, mid


def _overlaps(box, others) -> bool:
    return any(box[0] < o[2] and o[0] < box[2] and box[1] < o[3] and o[1] < box[3] for o in others)


def placed_edges(layout: Layout, edges: list[dict]) -> list[tuple[DrawnEdge, np.ndarray, np.ndarray, np.ndarray]]:
    """(edge, start, end, label centre) per drawn edge. A label goes to the first point along its
    line (middle first, then towards the ends) where it hides no node label and no other edge
    label; when none is free it stays in the middle."""
    taken = list(layout.boxes.values())
    out = []
    for e in drawn_edges(edges):
        g = _edge_geometry(layout, e)
        if g is None:
            continue
        a, b, mid = g
        w, h = text_size(", ".join(e.types), EDGE_FONT_SCALE)
        shift = mid - (a + b) / 2
        best = mid
        for t in (0.5, 0.38, 0.62, 0.28, 0.72, 0.2, 0.8):
            c = a + (b - a) * t + shift
            box = (c[0] - w / 2 - 1, c[1] - h / 2 - 1, c[0] + w / 2 + 1, c[1] + h / 2 + 1)
            if not _overlaps(box, taken):
                best = c
                break
        taken.append((best[0] - w / 2 - 1, best[1] - h / 2 - 1, best[0] + w / 2 + 1, best[1] + h / 2 + 1))
        out.append((e, a, b, best))
    return out


def _bgr(rgb):
    return (int(rgb[2]), int(rgb[1]), int(rgb[0]))


def _hex(rgb) -> str:
    return "#%02x%02x%02x" % tuple(int(c) for c in rgb)


def node_fill(node: dict, status: Optional[dict]) -> tuple[int, int, int]:
    if status is not None:
        return STATUS_COLOURS.get(status.get(node["id"], ""), (170, 170, 170))
    return category_colour(category_of(node.get("label") or "?"))


@dataclass
class Marker:
    """A hollow marker (a GT object the graph lacks) at a floor position."""
    text: str
    xy: np.ndarray


def legend_entries(scene: Scene, status: Optional[dict], markers: Sequence[Marker],
                   hidden: int) -> list[tuple[str, Optional[tuple[int, int, int]], str]]:
    """(text, colour, kind) rows; kind: 'fill', 'hollow' or 'text'."""
    rows: list[tuple[str, Optional[tuple[int, int, int]], str]] = []
    if status is not None:
        counts = {k: sum(v == k for v in status.values()) for k in STATUS_COLOURS}
        for k, c in STATUS_COLOURS.items():
            rows.append((f"{k} ({counts[k]})", c, "fill"))
        rows.append((f"missing GT ({len(markers)})", MISSING_COLOUR, "hollow"))
    else:
        groups = sorted({category_of(n.get("label") or "?") for n in scene.nodes})
        for g in groups:
            rows.append((g, category_colour(g), "fill"))
    rows.append((f"{len(scene.nodes)} nodes", None, "text"))
    if hidden:
        rows.append((f"{hidden} comparison edges hidden", None, "text"))
    return rows


# --------------------------------------------------------------------------- PNG


def render_png(scene: Scene, layout: Layout, edges: list[dict], *, status: Optional[dict] = None,
               markers: Sequence[Marker] = (), hidden: int = 0, title: str = "") -> np.ndarray:
    """The diagram as a BGR image (layout.height x layout.width)."""
    img = np.full((layout.height, layout.width, 3), BACKGROUND[::-1], np.uint8)
    names = display_names(scene.nodes, scene.edges)
    edge_col = (110, 110, 110)
    label_jobs = []
    for e, a, b, mid in placed_edges(layout, edges):
        pa, pb = tuple(int(round(v)) for v in a), tuple(int(round(v)) for v in b)
        tip = min(0.5, 9.0 / max(np.linalg.norm(b - a), 1.0))
        cv2.arrowedLine(img, pa, pb, edge_col, 1, cv2.LINE_AA, tipLength=tip)
        if e.both:
            cv2.arrowedLine(img, pb, pa, edge_col, 1, cv2.LINE_AA, tipLength=tip)
        label_jobs.append((", ".join(e.types), mid))
    # edge labels after all lines, on a white patch, so a later line never crosses a label
    for text, mid in label_jobs:
        w, h = text_size(text, EDGE_FONT_SCALE)
        x, y = int(mid[0] - w / 2), int(mid[1] + h / 2 - 2)
        cv2.rectangle(img, (x - 1, y - h + 2), (x + w + 1, y + 3), (255, 255, 255), -1)
        cv2.putText(img, text, (x, y), FONT, EDGE_FONT_SCALE, (60, 60, 160), 1, cv2.LINE_AA)
    if layout.to_pixels is not None:
        for m in markers:
            c = layout.to_pixels(m.xy)[0]
            ci = (int(round(c[0])), int(round(c[1])))
            cv2.circle(img, ci, NODE_R + 2, _bgr(MISSING_COLOUR), 2, cv2.LINE_AA)
            cv2.line(img, (ci[0] - 5, ci[1] - 5), (ci[0] + 5, ci[1] + 5), _bgr(MISSING_COLOUR), 1, cv2.LINE_AA)
            cv2.line(img, (ci[0] - 5, ci[1] + 5), (ci[0] + 5, ci[1] - 5), _bgr(MISSING_COLOUR), 1, cv2.LINE_AA)
            w, h = text_size(m.text)
            cv2.putText(img, m.text, (ci[0] - w // 2, ci[1] - NODE_R - 6), FONT, FONT_SCALE,
                        _bgr(MISSING_COLOUR), 1, cv2.LINE_AA)
    for n in scene.nodes:
        c = layout.pos[n["id"]]
        ci = (int(round(c[0])), int(round(c[1])))
        cv2.circle(img, ci, NODE_R, _bgr(node_fill(n, status)), -1, cv2.LINE_AA)
        cv2.circle(img, ci, NODE_R, (40, 40, 40), 1, cv2.LINE_AA)
        y = ci[1] + NODE_R + 4
        # a translucent white patch under the label: edges crossing it fade instead of striking it out
        x0, y0, x1, y1 = (int(round(v)) for v in layout.boxes[n["id"]])
        y0 = max(y0 + 2 * NODE_R + 2, 0)
        x0, x1, y1 = max(x0 - 2, 0), min(x1 + 2, layout.width), min(y1, layout.height)
        if x1 > x0 and y1 > y0:
            img[y0:y1, x0:x1] = (img[y0:y1, x0:x1] * 0.25 + 255 * 0.75).astype(np.uint8)
        for t in label_lines(names[n["id"]]):
            w, h = text_size(t)
            y += h
            # white halo first: node labels stay legible where edges cross them
            cv2.putText(img, t, (ci[0] - w // 2, y - 3), FONT, FONT_SCALE, (255, 255, 255), 4, cv2.LINE_AA)
            cv2.putText(img, t, (ci[0] - w // 2, y - 3), FONT, FONT_SCALE, (20, 20, 20), 1, cv2.LINE_AA)
            y += 2
    _png_legend(img, layout, legend_entries(scene, status, markers, hidden), title)
    return img


def _png_legend(img: np.ndarray, layout: Layout, rows, title: str) -> None:
    x0 = layout.width - LEGEND_W + 10
    y = 30
    if title:
        cv2.putText(img, title, (x0, y), FONT, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
        y += 24
    for text, colour, kind in rows:
        if colour is not None:
            if kind == "hollow":
                cv2.circle(img, (x0 + 7, y - 5), 7, _bgr(colour), 2, cv2.LINE_AA)
            else:
                cv2.circle(img, (x0 + 7, y - 5), 7, _bgr(colour), -1, cv2.LINE_AA)
        cv2.putText(img, text, (x0 + 22, y), FONT, FONT_SCALE, (30, 30, 30), 1, cv2.LINE_AA)
        y += 20
    if layout.scale > 0:
        # a 1 m scale bar: the top-down picture is a map
        bar = int(round(layout.scale))
        if 5 < bar < LEGEND_W - 30:
            yb = layout.height - 30
            cv2.line(img, (x0, yb), (x0 + bar, yb), (0, 0, 0), 2, cv2.LINE_AA)
            cv2.putText(img, "1 m (top-down)", (x0, yb - 8), FONT, FONT_SCALE, (0, 0, 0), 1, cv2.LINE_AA)


# --------------------------------------------------------------------------- SVG


def render_svg(scene: Scene, layout: Layout, edges: list[dict], *, status: Optional[dict] = None,
               markers: Sequence[Marker] = (), hidden: int = 0, title: str = "") -> str:
    """The same diagram as SVG text: one <g class="node"> with one <circle> per node, one
    <text class="edge-label"> per drawn edge."""
    esc = html.escape
    names = display_names(scene.nodes, scene.edges)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{layout.width}" height="{layout.height}" '
           f'viewBox="0 0 {layout.width} {layout.height}" font-family="Helvetica, Arial, sans-serif">',
           '<defs><marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" markerHeight="7" '
           'orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#6e6e6e"/></marker></defs>',
           f'<rect width="100%" height="100%" fill="{_hex(BACKGROUND)}"/>']
    labels = []
    out.append('<g class="edges">')
    for e, a, b, mid in placed_edges(layout, edges):
        start = ' marker-start="url(#arrow)"' if e.both else ""
        out.append(f'<line class="edge" data-s="{esc(e.s)}" data-o="{esc(e.o)}" x1="{a[0]:.1f}" y1="{a[1]:.1f}" '
                   f'x2="{b[0]:.1f}" y2="{b[1]:.1f}" stroke="#6e6e6e" stroke-width="1" '
                   f'marker-end="url(#arrow)"{start}/>')
        labels.append(f'<text class="edge-label" x="{mid[0]:.1f}" y="{mid[1] + 3:.1f}" font-size="10" '
                      f'fill="#a03c3c" text-anchor="middle" stroke="#fff" stroke-width="3" '
                      f'paint-order="stroke">{esc(", ".join(e.types))}</text>')
    out.append("</g>")
    out.append('<g class="edge-labels">' + "".join(labels) + "</g>")
    if layout.to_pixels is not None:
        for m in markers:
            c = layout.to_pixels(m.xy)[0]
            out.append(f'<g class="missing"><circle cx="{c[0]:.1f}" cy="{c[1]:.1f}" r="{NODE_R + 2}" fill="none" '
                       f'stroke="{_hex(MISSING_COLOUR)}" stroke-width="2" stroke-dasharray="4 2"/>'
                       f'<text x="{c[0]:.1f}" y="{c[1] - NODE_R - 6:.1f}" font-size="11" text-anchor="middle" '
                       f'fill="{_hex(MISSING_COLOUR)}">{esc(m.text)}</text></g>')
    for n in scene.nodes:
        c = layout.pos[n["id"]]
        lines = label_lines(names[n["id"]])
        text = "".join(f'<tspan x="{c[0]:.1f}" dy="{13 if i else 0}">{esc(t)}</tspan>' for i, t in enumerate(lines))
        out.append(f'<g class="node" id="{esc(n["id"])}"><title>{esc(n["id"])}</title>'
                   f'<circle cx="{c[0]:.1f}" cy="{c[1]:.1f}" r="{NODE_R}" fill="{_hex(node_fill(n, status))}" '
                   f'stroke="#282828"/><text x="{c[0]:.1f}" y="{c[1] + NODE_R + 14:.1f}" font-size="11" '
                   f'text-anchor="middle" stroke="#fff" stroke-width="3" paint-order="stroke">{text}</text></g>')
    x0, y = layout.width - LEGEND_W + 10, 30
    out.append('<g class="legend">')
    if title:
        out.append(f'<text x="{x0}" y="{y}" font-size="14">{esc(title)}</text>')
        y += 24
    for text, colour, kind in legend_entries(scene, status, markers, hidden):
        if colour is not None:
            fill = "none" if kind == "hollow" else _hex(colour)
            out.append(f'<circle cx="{x0 + 7}" cy="{y - 5}" r="7" fill="{fill}" stroke="{_hex(colour)}" stroke-width="2"/>')
        out.append(f'<text x="{x0 + 22}" y="{y}" font-size="12">{esc(text)}</text>')
        y += 20
    if layout.scale > 0 and 5 < layout.scale < LEGEND_W - 30:
        yb = layout.height - 30
        out.append(f'<line x1="{x0}" y1="{yb}" x2="{x0 + layout.scale:.1f}" y2="{yb}" stroke="#000" stroke-width="2"/>'
                   f'<text x="{x0}" y="{yb - 8}" font-size="12">1 m (top-down)</text>')
    out.append("</g></svg>")
    return "\n".join(out)


# --------------------------------------------------------------------------- 3-D HTML


def point_cloud(sequence_path, up: Sequence[float], frames: int = 8, max_points: int = 20000,
                stride: int = 8, max_depth: float = 4.0) -> list[list[float]]:
    """A coloured cloud from `frames` frames spread over the sequence, in the gravity frame
    (e1, e2, up), at most `max_points` points [a, b, h, r, g, b] (a seeded subsample)."""
    from ingest.readers import open_sequence

    seq = open_sequence(sequence_path)
    R = np.stack(horizontal_basis(up))
    picks = sorted({int(i) for i in np.linspace(0, len(seq) - 1, max(1, frames))})
    pts, cols = [], []
    for i in picks:
        try:
            f = seq.frame(i)
            depth, colour, K, pose = f.depth, f.color, f.K, f.pose
        except Exception:  # noqa: BLE001 - a bad frame only thins the cloud
            continue
        d = depth[::stride, ::stride].astype(np.float64)
        v, u = np.mgrid[0:d.shape[0], 0:d.shape[1]] * stride
        ok = (d > 0) & (d < max_depth) & np.isfinite(d)
        cam = np.stack([(u[ok] - K[0, 2]) / K[0, 0] * d[ok], (v[ok] - K[1, 2]) / K[1, 1] * d[ok], d[ok]], axis=1)
        world = cam @ pose[:3, :3].T + pose[:3, 3]
        pts.append(world @ R.T)
        cols.append(colour[v[ok], u[ok]][:, ::-1])        # BGR -> RGB
    if not pts:
        return []
    P, C = np.vstack(pts), np.vstack(cols)
    if len(P) > max_points:
        keep = np.sort(np.random.default_rng(0).choice(len(P), max_points, replace=False))
        P, C = P[keep], C[keep]
    return [[round(float(a), 3), round(float(b), 3), round(float(c), 3), int(r), int(g), int(bb)]
            for (a, b, c), (r, g, bb) in zip(P, C)]


def scene_3d(scene: Scene, edges: list[dict], up: Sequence[float]) -> dict:
    """Boxes and edges in the gravity frame (e1, e2, up): size (w, d, h) is measured along these
    axes, so each box is axis-aligned there and the viewer's z is up."""
    R = np.stack(horizontal_basis(up))
    names = display_names(scene.nodes, scene.edges)
    boxes = []
    for n in scene.nodes:
        c = R @ np.array([n.get("x") or 0.0, n.get("y") or 0.0, n.get("z") or 0.0])
        size = n.get("size") or [0.1, 0.1, 0.1]
        boxes.append({"id": n["id"], "name": names[n["id"]], "c": [round(float(v), 3) for v in c],
                      "s": [max(float(v), 0.03) for v in size],
                      "rgb": list(category_colour(category_of(n.get("label") or "?")))})
    return {"boxes": boxes, "edges": [{"s": e["s"], "o": e["o"], "t": e["type"]} for e in edges]}


_JS = r"""
const D = JSON.parse(document.getElementById('data').textContent);
const cv = document.getElementById('c'), g = cv.getContext('2d');
const byId = {}; D.boxes.forEach(b => byId[b.id] = b);
let yaw = -0.6, pitch = 0.9, zoom = 1, pan = [0, 0];
let showLabels = true, showCmp = D.cmp, showCloud = true;
// centre and radius of everything, so the first view frames the room
const all = D.boxes.map(b => b.c).concat(D.points.map(p => p.slice(0, 3)));
const ctr = [0, 1, 2].map(k => all.length ? all.reduce((s, p) => s + p[k], 0) / all.length : 0);
const rad = Math.max(1, ...all.map(p => Math.hypot(p[0] - ctr[0], p[1] - ctr[1], p[2] - ctr[2])));
function resize() { cv.width = innerWidth; cv.height = innerHeight - 40; draw(); }
// world (z up) -> camera -> perspective screen; returns null behind the camera
function proj(p) {
  const x = p[0] - ctr[0], y = p[1] - ctr[1], z = p[2] - ctr[2];
  const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
  const x1 = cy * x - sy * y, y1 = sy * x + cy * y;          // rotate about up
  const depth = cp * y1 + sp * z, up = -sp * y1 + cp * z;      // tilt the view
  const dist = rad * 2.5 / zoom, zc = dist + depth;
  if (zc < 0.05) return null;
  const f = Math.min(cv.width, cv.height) * 1.2;
  return [cv.width / 2 + pan[0] + f * x1 / zc, cv.height / 2 + pan[1] - f * up / zc, zc];
}
function line(a, b) { const p = proj(a), q = proj(b); if (!p || !q) return null;
  g.beginPath(); g.moveTo(p[0], p[1]); g.lineTo(q[0], q[1]); g.stroke(); return [(p[0] + q[0]) / 2, (p[1] + q[1]) / 2]; }
function draw() {
  g.fillStyle = '#111'; g.fillRect(0, 0, cv.width, cv.height);
  if (showCloud) for (const p of D.points) {
    const s = proj(p); if (!s) continue;
    g.fillStyle = `rgb(${p[3]},${p[4]},${p[5]})`; g.fillRect(s[0], s[1], 2, 2);
  }
  g.lineWidth = 1; g.font = '11px sans-serif';
  for (const e of D.edges) {
    if (!showCmp && (e.t === 'BIGGER_THAN' || e.t === 'SMALLER_THAN')) continue;
    const a = byId[e.s], b = byId[e.o]; if (!a || !b) continue;
    g.strokeStyle = 'rgba(255,255,120,0.7)'; const m = line(a.c, b.c);
    if (m && showLabels) { g.fillStyle = '#ffe680'; g.fillText(e.t, m[0] + 3, m[1]); }
  }
  for (const b of D.boxes) {
    const h = b.s.map(v => v / 2), c = b.c;
    const v = [];
    for (const dz of [-1, 1]) for (const dy of [-1, 1]) for (const dx of [-1, 1])
      v.push([c[0] + dx * h[0], c[1] + dy * h[1], c[2] + dz * h[2]]);
    g.strokeStyle = `rgb(${b.rgb.join(',')})`; g.lineWidth = 1.5;
    for (const [i, j] of [[0,1],[2,3],[4,5],[6,7],[0,2],[1,3],[4,6],[5,7],[0,4],[1,5],[2,6],[3,7]]) line(v[i], v[j]);
    const t = proj([c[0], c[1], c[2] + h[2]]);
    if (t && showLabels) { g.fillStyle = '#fff'; g.fillText(b.name, t[0] + 3, t[1] - 3); }
  }
}
let drag = null;
cv.addEventListener('mousedown', ev => drag = [ev.clientX, ev.clientY, ev.shiftKey]);
addEventListener('mouseup', () => drag = null);
addEventListener('mousemove', ev => {
  if (!drag) return;
  const dx = ev.clientX - drag[0], dy = ev.clientY - drag[1];
  if (drag[2]) { pan[0] += dx; pan[1] += dy; }
  else { yaw -= dx * 0.01; pitch = Math.max(-1.5, Math.min(1.5, pitch + dy * 0.01)); }
  drag = [ev.clientX, ev.clientY, drag[2]]; draw();
});
cv.addEventListener('wheel', ev => { ev.preventDefault(); zoom *= Math.exp(-ev.deltaY * 0.001); draw(); }, {passive: false});
for (const [id, set] of [['labels', v => showLabels = v], ['cmp', v => showCmp = v], ['cloud', v => showCloud = v]])
  document.getElementById(id).addEventListener('change', ev => { set(ev.target.checked); draw(); });
addEventListener('resize', resize); resize();
"""


def render_html(scene: Scene, edges: list[dict], up: Sequence[float], points: Optional[list] = None,
                title: str = "scene graph", show_comparisons: bool = False) -> str:
    """A self-contained page (no network): inline data and JS, orbit with the mouse. Every edge is
    embedded; comparison edges start hidden behind a checkbox unless `show_comparisons`."""
    data = scene_3d(scene, edges, up)
    data["points"] = points or []
    data["cmp"] = bool(show_comparisons)
    # "</" must not end the <script> element early; JSON allows "<\/"
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return (
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + html.escape(title) + "</title>\n"
        "<style>body{margin:0;background:#111;color:#ddd;font:13px sans-serif}"
        "#bar{height:40px;display:flex;gap:16px;align-items:center;padding:0 10px}</style></head>\n"
        "<body><div id=\"bar\"><b>" + html.escape(title) + "</b>"
        f"<span>{len(data['boxes'])} objects, {len(data['edges'])} edges, {len(data['points'])} points</span>"
        "<label><input type=\"checkbox\" id=\"labels\" checked> labels</label>"
        "<label><input type=\"checkbox\" id=\"cmp\"" + (" checked" if show_comparisons else "") + "> comparison edges</label>"
        "<label><input type=\"checkbox\" id=\"cloud\" checked> point cloud</label>"
        "<span>drag: rotate, shift+drag: pan, wheel: zoom</span></div>\n"
        "<canvas id=\"c\"></canvas>\n"
        "<script type=\"application/json\" id=\"data\">" + payload + "</script>\n"
        "<script>" + _JS + "</script>\n</body></html>\n")


# --------------------------------------------------------------------------- one call


def render(scene: Scene, fmt: str, *, width: int = 1600, height: int = 1200, layout: str = "topdown",
           all_edges: bool = False, status: Optional[dict] = None, markers: Sequence[Marker] = (),
           title: str = "", points: Optional[list] = None):
    """PNG -> encoded bytes, SVG/HTML -> text."""
    edges = visible_edges(scene.edges, all_edges)
    hidden = len(scene.edges) - len(edges)
    if fmt == "html":
        rooms = sorted({n.get("room_name") or "" for n in scene.nodes})
        up = room_up(scene, rooms[0]) if rooms else np.array([0.0, 0.0, 1.0])
        return render_html(scene, scene.edges, up, points, title or "scene graph", show_comparisons=all_edges)
    extra = np.array([m.xy for m in markers]).reshape(-1, 2) if markers else None
    lay = make_layout(scene, width, height, layout, edges, extra)
    if fmt == "png":
        img = render_png(scene, lay, edges, status=status, markers=markers, hidden=hidden, title=title)
        ok, buf = cv2.imencode(".png", img)
        if not ok:
            raise RuntimeError("PNG encoding failed")
        return buf.tobytes()
    if fmt == "svg":
        return render_svg(scene, lay, edges, status=status, markers=markers, hidden=hidden, title=title)
    raise ValueError(f"unknown format {fmt!r}")
