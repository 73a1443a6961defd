"""The 2-D node-link diagram (`sg3d show --out g.png|.svg|.pdf`, the eval report's picture),
drawn with matplotlib; positions from the objects (top-down) or from networkx (spring).

Top-down: every node sits exactly at its object's floor position (position mean projected on
the room's floor plane, `sg3d.render.geometry`), on a metre grid with a scale bar; rooms are outlined
and, in a building, named. Labels never overlap: they are placed around their node
(`sg3d.render.labels`), with a leader line when pushed out, and a label with no free place becomes a
number whose name is in the side table. Each pair of objects gets one line whose label merges
its statements ("on / smaller than"); a label that does not fit on its line goes to the side
table too. Comparison edges (BIGGER_THAN/SMALLER_THAN) are hidden unless `all_edges`.
"""
from __future__ import annotations

import io
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional, Sequence

import numpy as np

from sg3d.core.stored import Scene, StoredObject
from sg3d.render import labels as L
from sg3d.render.geometry import drawing_frame, room_outlines
from sg3d.render.style import (
    MISSING_COLOUR,
    STATUS_COLOURS,
    category_colour,
    category_of,
    pair_edges,
    visible_edges,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

FORMATS = ("png", "svg", "pdf")
LAYOUTS = ("topdown", "spring")
DPI = 100
PLOT_RECT = (0.035, 0.045, 0.685, 0.90)       # left, bottom, width, height of the map (figure fraction)
SIDE_TABLE_PT = 7.5                           # the side table's font size and line spacing
SIDE_TABLE_SPACING = 1.25
SIDE_TABLE_FOOT = 0.08                        # figure fraction it stops at: the scale bar is below
PANEL_X = 0.74                              # the legend and side table column starts here
NODE_SIZE = 90                              # scatter marker area, points^2
NODE_R_PX = 6.5
LABEL_FONT = 8.5
EDGE_FONT = 7.0
SCALE_CHOICES = (0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0)
PAD_M = 0.5


@dataclass
class Marker:
    """A hollow marker (a ground-truth object the graph lacks) at a world position of a room."""
    text: str
    xyz: Sequence[float]
    room: str


@dataclass
class Diagram:
    figure: Figure
    ax: Axes
    node_px: dict[str, tuple[float, float]]               # id -> display pixel (x, y up)
    node_xy: dict[str, tuple[float, ...]]                 # id -> data coordinates (metres top-down)
    labels: list = field(default_factory=list)            # node label Text artists
    edge_labels: list = field(default_factory=list)       # edge label Text artists
    listed_nodes: list[str] = field(default_factory=list)     # side-table rows for unplaced names
    listed_edges: list[str] = field(default_factory=list)     # side-table rows for unplaced edge labels
    scale_m: float = 0.0                                  # scale bar length (0: no scale, spring)
    scale_px: float = 0.0

    def save(self, fmt: str) -> bytes:
        import matplotlib

        buf = io.BytesIO()
        meta = {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[fmt]
        # SVG text as <text>, not glyph outlines: searchable, selectable, smaller; fixed ids: same bytes
        with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "sg3d"}):
            self.figure.savefig(buf, format=fmt, dpi=DPI, metadata=meta)
        return buf.getvalue()


def label_lines(name: str) -> str:
    """"red cup on the dining table" on two lines: narrower labels find a free place more often."""
    for sep in (" on the ", " in the "):
        if sep in name:
            head, tail = name.split(sep, 1)
            return head + "\n" + sep.strip() + " " + tail
    return name


def node_colour(node: StoredObject, status: Optional[dict]) -> str:
    if status is not None:
        return STATUS_COLOURS.get(status.get(node.id, ""), "#aaaaaa")
    return category_colour(category_of(node.label or "?"))


def spring_positions(scene: Scene, seed: int = 0) -> dict[str, np.ndarray]:
    """networkx's spring layout (seeded: the same graph gives the same picture) over the spatial
    edges only (size statements link nearly every pair and would squash it into a ball), one
    connected component at a time, the components packed in rows, largest first: a force layout
    of the whole graph throws unconnected objects to the rim and shrinks the rest."""
    import networkx as nx

    g = nx.Graph()
    g.add_nodes_from(sorted(n.id for n in scene.nodes))
    for e in visible_edges(scene.edges, all_edges=False):
        if e.s in g and e.o in g and e.s != e.o:
            g.add_edge(e.s, e.o)
    comps = sorted((sorted(c) for c in nx.connected_components(g)), key=lambda c: (-len(c), c[0]))
    blocks = []
    for comp in comps:
        sub = g.subgraph(comp)
        if len(comp) == 1:
            blocks.append({comp[0]: np.zeros(2)})
            continue
        pos = nx.spring_layout(sub, seed=seed, k=1.0 / np.sqrt(len(comp)), iterations=300)
        blocks.append({k: np.asarray(v) * np.sqrt(len(comp)) for k, v in pos.items()})
    total = sum(len(b) for b in blocks)
    row_w = max(4.0, 2.2 * np.sqrt(total))
    out, x, y, row_h = {}, 0.0, 0.0, 0.0
    for b in blocks:
        pts = np.array(list(b.values()))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        w, h = hi - lo + 1.2           # a gap between components
        if x > 0 and x + w > row_w:
            x, y, row_h = 0.0, y - row_h, 0.0
        for k, v in b.items():
            out[k] = v - lo + np.array([x, y - (hi[1] - lo[1])])
        x += w
        row_h = max(row_h, h)
    return out


def scale_length(px_per_m: float, max_px: float) -> float:
    """The longest round length (0.1 m ... 10 m) whose bar fits in `max_px`."""
    fits = [s for s in SCALE_CHOICES if s * px_per_m <= max_px]
    return fits[-1] if fits else SCALE_CHOICES[0]


def _limits(points: np.ndarray, aspect: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """Data limits around `points` (padded) widened so one metre is as long on both axes."""
    lo, hi = points.min(axis=0) - PAD_M, points.max(axis=0) + PAD_M
    w, h = hi - lo
    if w / h < aspect:
        extra = (h * aspect - w) / 2
        lo[0], hi[0] = lo[0] - extra, hi[0] + extra
    else:
        extra = (w / aspect - h) / 2
        lo[1], hi[1] = lo[1] - extra, hi[1] + extra
    return (lo[0], hi[0]), (lo[1], hi[1])


class _Canvas:
    """The figure being drawn and what label placement measures with: the renderer, the display
    pixels already taken (`sg3d.render.labels.Occupancy`) and the map's bounds."""

    def __init__(self, fig, ax):
        fig.canvas.draw()               # fixes the transforms the placement below measures with
        self.fig, self.ax = fig, ax
        self.renderer = fig.canvas.get_renderer()
        self.to_px = ax.transData.transform
        bbox = ax.get_window_extent(self.renderer)
        self.bounds = (bbox.x0 + 2, bbox.y0 + 2, bbox.x1 - 2, bbox.y1 - 2)
        self.occ = L.Occupancy()

    def text_size(self, text: str, fontsize: float, **kw) -> tuple[float, float]:
        t = self.ax.text(0, 0, text, fontsize=fontsize, **kw)
        ext = t.get_window_extent(self.renderer)
        t.remove()
        return ext.width + 4, ext.height + 2

    def put(self, text: str, anchor, fontsize: float, colour: str, leader_colour: str = "#999999", **kw):
        """A label near `anchor` (display pixels) where it overlaps nothing; None: no free place."""
        ax = self.ax
        w, h = self.text_size(text, fontsize, **kw)
        spot = L.place(anchor, (w, h), self.occ, self.bounds)
        if spot is None:
            return None
        if spot.leader:
            # from the anchor to the nearest point of the label's box
            bx = min(max(anchor[0], spot.box[0]), spot.box[2])
            by = min(max(anchor[1], spot.box[1]), spot.box[3])
            inv = ax.transData.inverted()
            (x0, y0), (x1, y1) = inv.transform(anchor), inv.transform((bx, by))
            ax.plot([x0, x1], [y0, y1], color=leader_colour, linewidth=0.6, zorder=2.5)
        xy = ax.transData.inverted().transform(spot.centre)
        return ax.text(xy[0], xy[1], text, fontsize=fontsize, color=colour, ha="center", va="center",
                       zorder=4, **kw)


@dataclass
class _Labels:
    """What the label passes placed, and what went to the side table instead."""
    texts: list = field(default_factory=list)             # room names
    markers: list = field(default_factory=list)           # missing-object markers' texts
    nodes: list = field(default_factory=list)             # node label artists
    edges: list = field(default_factory=list)             # edge label artists
    listed_nodes: list[str] = field(default_factory=list)
    listed_edges: list[str] = field(default_factory=list)


def draw(scene: Scene, *, layout: str = "topdown", all_edges: bool = False, size=(1600, 1200),
         status: Optional[dict] = None, markers: Sequence[Marker] = (), title: str = "") -> Diagram:
    """The diagram of `scene` (sg3d.app.scene.fetch_scene). `status`: node id -> matched / spurious /
    duplicate (the eval report colours nodes by it instead of by category)."""
    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r}")
    width, height = size
    nodes = sorted(scene.nodes, key=lambda n: n.id)
    topdown = layout == "topdown"
    frame = drawing_frame(scene) if topdown else None
    if topdown:
        assert frame is not None
        pos = {i: c[:2] for i, c in frame.coords.items()}
        outlines = room_outlines(scene, frame)
        marker_xy = [frame.placements[m.room].apply(m.xyz)[0, :2] for m in markers if m.room in frame.placements]
    else:
        pos, outlines, marker_xy = spring_positions(scene), {}, []
    fig, ax = _map_axes(size, pos, outlines, marker_xy, topdown)
    canvas = _Canvas(fig, ax)
    _draw_rooms(ax, outlines)
    pairs = [p for p in pair_edges(visible_edges(scene.edges, all_edges)) if p.s in pos and p.o in pos]
    _draw_edges(ax, pos, pairs, topdown)
    node_px = _draw_nodes(canvas, nodes, pos, status, markers, marker_xy)
    names = {n.id: n.name or n.label or n.id for n in nodes}
    placed = _Labels()
    _label_rooms_and_markers(canvas, placed, outlines, markers, marker_xy)
    _label_nodes(canvas, placed, nodes, node_px, names)
    _label_edges(canvas, placed, pairs, node_px, names)
    # the right-hand column: title, legend, scale bar, then the side table
    hidden = len(scene.edges) - len(visible_edges(scene.edges, all_edges))
    summary = _summary(len(nodes), len(pairs), hidden, frame, len(outlines))
    y = _panel_head(canvas, title, summary, _legend_handles(nodes, pairs, status, markers, outlines), height)
    scale_m, scale_px = _scale_bar(canvas, size) if topdown else (0.0, 0.0)
    _side_table(fig, placed, y, height)
    return Diagram(fig, ax, node_px, {i: tuple(map(float, p)) for i, p in pos.items()},
                   placed.nodes + placed.texts + placed.markers, placed.edges, placed.listed_nodes,
                   placed.listed_edges, scale_m, scale_px)


def _map_axes(size, pos: dict, outlines: dict, marker_xy: list, topdown: bool):
    """The figure and its map axes: limits around everything drawn, one metre as long on both
    axes; top-down on a metre grid."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import MultipleLocator

    width, height = size
    fig = Figure(figsize=(width / DPI, height / DPI), dpi=DPI)
    FigureCanvasAgg(fig)            # no pyplot: no global state, safe in a server thread
    fig.patch.set_facecolor("white")
    ax = fig.add_axes(PLOT_RECT)
    pts = [np.array(list(pos.values()))] + [o for o in outlines.values()] + \
          ([np.array(marker_xy)] if marker_xy else [])
    xlim, ylim = _limits(np.vstack(pts), (PLOT_RECT[2] * width) / (PLOT_RECT[3] * height))
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    ax.set_autoscale_on(False)
    if topdown:
        ax.xaxis.set_major_locator(MultipleLocator(1.0))
        ax.yaxis.set_major_locator(MultipleLocator(1.0))
        ax.xaxis.set_major_formatter("{x:g} m")
        ax.yaxis.set_major_formatter("{x:g} m")
        ax.grid(True, color="#e4e4e4", linewidth=0.8, zorder=0)
        ax.tick_params(labelsize=7, colors="#888888", length=0)
        ax.set_axisbelow(True)
        for side in ax.spines.values():
            side.set_color("#cccccc")
    else:
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_frame_on(False)
    return fig, ax


def _draw_rooms(ax, outlines: dict) -> None:
    """Each room's outline, dashed, over a light fill."""
    for r, poly in sorted(outlines.items()):
        ax.plot(poly[:, 0], poly[:, 1], color="#7a7a7a", linewidth=1.2, linestyle=(0, (6, 3)), zorder=1)
        ax.fill(poly[:, 0], poly[:, 1], color="#f4f1ea", zorder=0.5)


def _draw_edges(ax, pos: dict, pairs: list, topdown: bool) -> None:
    """One line per pair (networkx draws them, arrows stopping at the node markers)."""
    import networkx as nx

    g = nx.DiGraph()
    g.add_nodes_from(pos)
    for group, style, colour, arrows in (
            ([p for p in pairs if p.comparison], (0, (3, 3)), "#b9b9b9", True),
            ([p for p in pairs if not p.comparison and p.directed], "solid", "#5c5c5c", True),
            ([p for p in pairs if not p.directed], "solid", "#5c5c5c", False)):
        if group:
            nx.draw_networkx_edges(g, pos, edgelist=[(p.s, p.o) for p in group], ax=ax, arrows=True,
                                   arrowstyle="-|>" if arrows else "-", arrowsize=9, width=0.9,
                                   edge_color=colour, style=style, node_size=NODE_SIZE,
                                   min_source_margin=2, min_target_margin=2)
    if topdown:     # networkx's edge drawing switches tick labels off; the metre grid keeps them
        ax.tick_params(labelbottom=True, labelleft=True)


def _draw_nodes(canvas: _Canvas, nodes: list[StoredObject], pos: dict, status: Optional[dict],
                markers: Sequence[Marker], marker_xy: list) -> dict[str, tuple[float, float]]:
    """One scatter per node (an SVG group with the node's id) at the object's position, then the
    missing-object markers; their pixels are taken for labels. Returns id -> display pixel."""
    ax, node_px = canvas.ax, {}
    for n in nodes:
        x, y = pos[n.id]
        ax.scatter([x], [y], s=NODE_SIZE, c=node_colour(n, status), edgecolors="#222222", linewidths=0.8,
                   zorder=3, gid=f"node-{n.id}")
        px = canvas.to_px((x, y))
        node_px[n.id] = (float(px[0]), float(px[1]))
        canvas.occ.add((px[0] - NODE_R_PX, px[1] - NODE_R_PX, px[0] + NODE_R_PX, px[1] + NODE_R_PX))
    for m, xy in zip(markers, marker_xy):
        ax.scatter([xy[0]], [xy[1]], s=NODE_SIZE * 1.6, facecolors="none", edgecolors=MISSING_COLOUR,
                   linewidths=1.6, linestyle="--", zorder=3)
        ax.scatter([xy[0]], [xy[1]], s=30, marker="x", c=MISSING_COLOUR, linewidths=1, zorder=3)
        px = canvas.to_px(xy)
        canvas.occ.add((px[0] - NODE_R_PX - 2, px[1] - NODE_R_PX - 2, px[0] + NODE_R_PX + 2, px[1] + NODE_R_PX + 2))
    return node_px


def _label_rooms_and_markers(canvas: _Canvas, placed: _Labels, outlines: dict, markers: Sequence[Marker],
                             marker_xy: list) -> None:
    """Room names first (few, and a building picture must name its rooms), then missing markers."""
    if len(outlines) > 1:
        for r, poly in sorted(outlines.items()):
            top = poly[np.argmax(poly[:, 1])]
            t = canvas.put(r, canvas.to_px(top), 11, "#555555", weight="bold")
            if t is not None:
                placed.texts.append(t)
    for m, xy in zip(markers, marker_xy):
        t = canvas.put(m.text, canvas.to_px(xy), LABEL_FONT - 1, MISSING_COLOUR, leader_colour=MISSING_COLOUR)
        if t is not None:
            placed.markers.append(t)
        else:
            placed.listed_nodes.append(f"missing: {m.text}")


def _label_nodes(canvas: _Canvas, placed: _Labels, nodes: list[StoredObject], node_px: dict, names: dict) -> None:
    """Node labels, the most crowded first (they need the most choices); a name with no free
    place becomes a number listed in the side table."""
    crowd = {}
    all_px = np.array([node_px[n.id] for n in nodes])
    for n in nodes:
        d = np.linalg.norm(all_px - np.array(node_px[n.id]), axis=1)
        crowd[n.id] = int((d < 90).sum())
    order = sorted(nodes, key=lambda n: (-crowd[n.id], n.id))
    numbered = []
    for n in order:
        t = canvas.put(label_lines(names[n.id]), node_px[n.id], LABEL_FONT, "#1a1a1a",
                       bbox=None, linespacing=1.0)
        if t is not None:
            t.set_gid(f"label-{n.id}")
            placed.nodes.append(t)
        else:
            numbered.append(n)
    for k, n in enumerate(sorted(numbered, key=lambda n: names[n.id]), 1):
        t = canvas.put(str(k), node_px[n.id], LABEL_FONT - 1, "#1a1a1a")
        if t is not None:
            t.set_gid(f"label-{n.id}")
            placed.nodes.append(t)
            placed.listed_nodes.append(f"{k}  {names[n.id]}")
        else:
            placed.listed_nodes.append(f"·  {names[n.id]}")


def _label_edges(canvas: _Canvas, placed: _Labels, pairs: list, node_px: dict, names: dict) -> None:
    """Edge labels where they fit on their line; the rest go to the side table."""
    for p in sorted(pairs, key=lambda p: (p.comparison, names[p.s], names[p.o])):
        text = p.label
        w, h = canvas.text_size(text, EDGE_FONT)
        spot = L.place_on_segment(node_px[p.s], node_px[p.o], (w, h), canvas.occ, canvas.bounds)
        arrow = "→" if p.directed else "–"
        if spot is None:
            placed.listed_edges.append(f"{names[p.s]} {arrow} {names[p.o]}: {text}")
            continue
        xy = canvas.ax.transData.inverted().transform(spot.centre)
        t = canvas.ax.text(xy[0], xy[1], text, fontsize=EDGE_FONT, color="#8a2a2a", ha="center", va="center",
                           zorder=3.5, bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.9))
        t.set_gid(f"edge-label-{p.s}-{p.o}")
        placed.edges.append(t)


def _summary(n_nodes: int, n_pairs: int, hidden: int, frame, n_rooms: int) -> str:
    """The lines under the title: what is drawn, what is hidden, what the positions mean."""
    summary = f"{n_nodes} objects, {n_pairs} related pairs"
    if hidden:
        summary += f"\n{hidden} size statements hidden (--all-edges)"
    if frame is not None:
        summary += "\ntop-down, metre grid" + ("" if (frame.aligned or n_rooms < 2)
                                               else "\nrooms not aligned: side by side")
    else:
        summary += "\nspring layout: distances mean nothing"
    return summary


def _legend_handles(nodes: list[StoredObject], pairs: list, status: Optional[dict], markers: Sequence[Marker],
                    outlines: dict) -> list:
    """Legend entries: node colours (by eval status or by category), then the line and room styles."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles: list[Line2D | Patch] = []
    if status is not None:
        counts = {k: sum(v == k for v in status.values()) for k in STATUS_COLOURS}
        handles += [Line2D([], [], marker="o", linestyle="", markersize=8, markerfacecolor=c,
                           markeredgecolor="#222222", label=f"{k} ({counts[k]})") for k, c in STATUS_COLOURS.items()]
        handles.append(Line2D([], [], marker="o", linestyle="", markersize=9, markerfacecolor="none",
                              markeredgecolor=MISSING_COLOUR, label=f"missing ground truth ({len(markers)})"))
    else:
        groups = sorted({category_of(n.label or "?") for n in nodes})
        handles += [Line2D([], [], marker="o", linestyle="", markersize=8, markerfacecolor=category_colour(gname),
                           markeredgecolor="#222222", label=gname) for gname in groups]
    handles.append(Line2D([], [], color="#5c5c5c", linewidth=1, label="relation (label: all its statements)"))
    if any(p.comparison for p in pairs):
        handles.append(Line2D([], [], color="#b9b9b9", linewidth=1, linestyle=(0, (3, 3)), label="size only"))
    if outlines:
        handles.append(Patch(facecolor="#f4f1ea", edgecolor="#7a7a7a", linestyle="--", label="room (its objects' extent)"))
    return handles


def _panel_head(canvas: _Canvas, title: str, summary: str, handles: list, height: int) -> float:
    """Title, summary and legend at the top of the right-hand column; returns the figure height
    fraction below them."""
    fig, y = canvas.fig, 0.965
    fig.text(PANEL_X, y, title or "scene graph", fontsize=13, weight="bold", va="top")
    y -= 0.035
    fig.text(PANEL_X, y, summary, fontsize=8.5, va="top", color="#444444", linespacing=1.3)
    y -= 0.022 * (summary.count("\n") + 1) + 0.012
    legend = fig.legend(handles=handles, loc="upper left", bbox_to_anchor=(PANEL_X - 0.005, y), fontsize=8,
                        frameon=False, handlelength=1.6, borderaxespad=0, ncols=1 if len(handles) <= 16 else 2)
    fig.canvas.draw()
    leg = legend.get_window_extent(canvas.renderer)
    return leg.y0 / height - 0.02


def _scale_bar(canvas: _Canvas, size) -> tuple[float, float]:
    """A round-length scale bar at the foot of the column; returns (metres, pixels)."""
    from matplotlib.lines import Line2D

    width, _ = size
    px_per_m = float(canvas.to_px((1.0, 0.0))[0] - canvas.to_px((0.0, 0.0))[0])
    scale_m = scale_length(px_per_m, 0.6 * (0.98 - PANEL_X) * width)
    scale_px = scale_m * px_per_m
    yb = 0.035
    canvas.fig.add_artist(Line2D([PANEL_X, PANEL_X + scale_px / width], [yb, yb], color="black", linewidth=3,
                                 solid_capstyle="butt", gid="scalebar"))
    canvas.fig.text(PANEL_X, yb + 0.008, f"{scale_m:g} m" if scale_m >= 1 else f"{scale_m * 100:g} cm",
                    fontsize=9, va="bottom", gid="scalebar-label")
    return scale_m, scale_px


def _side_table(fig, placed: _Labels, y: float, height: int) -> None:
    """The names and relations that found no place on the map, as many as the column holds."""
    listed_edges = placed.listed_edges
    rows = placed.listed_nodes + ([""] + ["relations without room on their line:"] + listed_edges if listed_edges else [])
    # a text line's height at the figure's resolution; the table ends above the scale bar
    line_h = SIDE_TABLE_PT * SIDE_TABLE_SPACING * DPI / 72 / height
    room_for = max(0, int((y - SIDE_TABLE_FOOT) / line_h))
    if rows and room_for:
        shown = rows[:room_for] if len(rows) <= room_for else rows[:room_for - 1] + [
            f"+ {len(rows) - room_for + 1} more (sg3d export lists every relation)"]
        fig.text(PANEL_X, y, "\n".join(_clip(r, 58) for r in shown), fontsize=SIDE_TABLE_PT, va="top",
                 color="#333333", linespacing=SIDE_TABLE_SPACING, gid="side-table")


def _clip(text: str, n: int) -> str:
    return text if len(text) <= n else text[:n - 1] + "…"


def render_diagram(scene: Scene, fmt: str, **kw) -> bytes:
    """The diagram as PNG, SVG or PDF bytes (`draw`'s keywords)."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown format {fmt!r}")
    return draw(scene, **kw).save(fmt)
