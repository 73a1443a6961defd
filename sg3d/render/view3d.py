"""The interactive 3-D view (`sg3d show --out g.html`): one self-contained HTML file drawn by
plotly (WebGL), plotly.js inlined so it opens offline.

What a person sees first: the room from above at an angle, framed on its objects (axis ranges
from the boxes and the bulk of the cloud, so stray depth points far away do not shrink it),
filling the window (no scrollbars). Object boxes are translucent, coloured by category (the
room's structure, floor, walls, counters and shelves, fainter), every box named on hover.
Names on the page: only the objects a detector named (chair, cup, tv, ...) by default; the
unnamed objects and the structure are one legend-only trace ("other names"). Why: the kitchen
holds 33 of those against 13 named objects, and their names, on large boxes around the room's
rim, piled up along the walls over everything behind them. Names that would print over each
other in the first view (their text boxes projected as plotly first draws the scene) are
raised, each raised one joined to its box by a thin leader.
Relation lines: one trace per stored type in its own colour (sg3d.render.style.RELATION_COLOURS),
in a second legend, "relations", so each type is toggled on its own; size statements are dotted
and start hidden (legend-only) unless `all_edges`. The point cloud is one trace of at most the
points given (already thinned by sg3d.app.scene.sequence_cloud); a building shows its rooms'
outlines and names on the floor. Axes are titled in metres ("x (m)", "y (m)", "up (m)"; x, y
horizontal, up against gravity) with a 1 m grid.
"""
from __future__ import annotations

import html as htmlmod
from typing import Optional

import numpy as np

from sg3d.core.model import UNNAMED_LABEL
from sg3d.core.stored import Scene, StoredObject, StoredRelation
from sg3d.render.geometry import box_corners, drawing_frame, room_outlines
from sg3d.render.labels import overlaps
from sg3d.render.style import (
    COMPARISON_TYPES,
    category_colour,
    category_of,
    pair_edges,
    relation_colour,
    word,
)

# 12 triangles of a box whose corners come in box_corners' order (x fastest, then y, then z)
_TRIS = np.array([[0, 1, 3], [0, 3, 2], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 3, 7], [1, 7, 5]])
_EDGES = [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)]
CLOUD_QUANTILES = (0.01, 0.99)      # the first view frames the bulk of the cloud, not its outliers
FRAME_PAD_M = 0.3
LARGE_M = 0.6             # footprint diagonal above which a name goes to a corner, not the middle
OBJECT_OPACITY, STRUCTURE_OPACITY = 0.25, 0.08      # structure boxes are large: faint, so objects show
CAMERA_EYE = (-0.65, -1.1, 0.85)     # the first view: from above at an angle
# Names are kept apart in that first view, seen as plotly draws it in a 1400 x 900 window: the
# scene's largest span is about 620 px wide there (measured on screenshots: 680 px at 1400 x
# 1000, within 8 px of an orthographic projection), 12 px text ~5.6 px a character, 16 px a line.
FIRST_VIEW_PX, CHAR_PX, LINE_PX = 620.0, 5.6, 16.0
RELATIONS_LEGEND = "legend2"


def _hex_rgb(c: str) -> tuple[int, int, int]:
    c = c.lstrip("#")
    return int(c[0:2], 16), int(c[2:4], 16), int(c[4:6], 16)


def figure(scene: Scene, cloud: Optional[tuple] = None, all_edges: bool = False, title: str = "scene graph"):
    """The plotly Figure. `cloud`: (points N x 3 in the first room's world frame, colours N x 3
    uint8), from sg3d.app.scene.sequence_cloud."""
    import plotly.graph_objects as go

    frame = drawing_frame(scene)
    nodes = sorted(scene.nodes, key=lambda n: n.id)
    names = {n.id: n.name or n.label or n.id for n in nodes}
    room_of = {n.id: n.room_name or "" for n in nodes}
    corners = {n.id: box_corners(n, frame.placements[room_of[n.id]]) for n in nodes}
    # the cloud first, so boxes and lines draw over it
    extent = [np.vstack(list(corners.values()))]
    traces = _cloud_traces(frame, cloud, extent)
    traces += _box_traces(nodes, corners, names, room_of)
    lo, hi = np.vstack(extent).min(axis=0) - FRAME_PAD_M, np.vstack(extent).max(axis=0) + FRAME_PAD_M
    traces += _name_traces(nodes, corners, names, (lo + hi) / 2, float((hi - lo).max()))
    traces += _relation_traces(scene.edges, nodes, corners, names, all_edges)
    traces += _room_traces(room_outlines(scene, frame), corners)
    fig = go.Figure(traces)
    _lay_out(fig, lo, hi, title)
    return fig


def is_named(node: StoredObject) -> bool:
    """A detector named it: not the room's structure and not an unnamed object."""
    return node.layer != "structure" and (node.label or UNNAMED_LABEL) != UNNAMED_LABEL


def _cloud_traces(frame, cloud: Optional[tuple], extent: list) -> list:
    """The point cloud as one trace; the bulk of it (not its outliers) joins `extent`."""
    import plotly.graph_objects as go

    if cloud is None or not len(cloud[0]):
        return []
    rooms = sorted(frame.placements)
    P = frame.placements[rooms[0]].apply(cloud[0])
    lo, hi = np.quantile(P, CLOUD_QUANTILES[0], axis=0), np.quantile(P, CLOUD_QUANTILES[1], axis=0)
    extent.append(np.array([lo, hi]))
    C = np.asarray(cloud[1], dtype=np.uint8)
    colours = ["#%02x%02x%02x" % tuple(c) for c in C]
    return [go.Scatter3d(x=P[:, 0].astype(np.float32), y=P[:, 1].astype(np.float32),
                         z=P[:, 2].astype(np.float32), mode="markers", name=f"point cloud ({len(P):,})",
                         marker=dict(size=1.6, color=colours), hoverinfo="skip", legendgroup="cloud")]


def _box_traces(nodes: list[StoredObject], corners: dict, names: dict, room_of: dict) -> list:
    """Boxes: one mesh + one wireframe per category, so the legend toggles a category."""
    import plotly.graph_objects as go

    by_cat: dict[str, list[StoredObject]] = {}
    for n in nodes:
        by_cat.setdefault(category_of(n.label or "?"), []).append(n)
    traces = []
    for cat in sorted(by_cat):
        colour = category_colour(cat)
        xs: list[float]
        xs, ys, zs, ii, jj, kk, text = [], [], [], [], [], [], []
        lx, ly, lz = [], [], []
        for n in by_cat[cat]:
            c = corners[n.id]
            base = len(xs)
            xs += c[:, 0].tolist()
            ys += c[:, 1].tolist()
            zs += c[:, 2].tolist()
            ii += (_TRIS[:, 0] + base).tolist()
            jj += (_TRIS[:, 1] + base).tolist()
            kk += (_TRIS[:, 2] + base).tolist()
            size = n.size or [0, 0, 0]
            hover = (f"<b>{htmlmod.escape(names[n.id])}</b><br>{htmlmod.escape(n.label or '')}"
                     f" · {htmlmod.escape(n.colour or '')}<br>{size[0]:.2f} × {size[1]:.2f} × {size[2]:.2f} m"
                     f"<br>room {htmlmod.escape(room_of[n.id])}")
            text += [hover] * 8
            for a, b in _EDGES:
                lx += [c[a, 0], c[b, 0], None]
                ly += [c[a, 1], c[b, 1], None]
                lz += [c[a, 2], c[b, 2], None]
        structure = all(n.layer == "structure" for n in by_cat[cat])
        traces.append(go.Mesh3d(x=xs, y=ys, z=zs, i=ii, j=jj, k=kk, color=colour, name=cat,
                                opacity=STRUCTURE_OPACITY if structure else OBJECT_OPACITY,
                                legendgroup=cat, showlegend=True, hovertext=text, hoverinfo="text",
                                flatshading=True))
        traces.append(go.Scatter3d(x=lx, y=ly, z=lz, mode="lines", line=dict(color=colour, width=2 if structure else 3),
                                   legendgroup=cat, showlegend=False, hoverinfo="skip", name=cat))
    return traces


def _name_spot(c: np.ndarray) -> list[float]:
    """Where a box's name goes: above its middle, or for a large object above the top corner
    facing the first view, so the name of a cup standing in its middle stays readable."""
    lo, hi = c.min(axis=0), c.max(axis=0)
    if np.hypot(*(hi - lo)[:2]) > LARGE_M:
        return [lo[0], lo[1], hi[2] + 0.04]
    return [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 0.04]


def screen_boxes(spots: np.ndarray, texts: list[str], mid: np.ndarray, span: float) -> list[tuple]:
    """Each name's box (x0, y0, x1, y1 in pixels, y up) in the first view of a scene framed on
    `mid` and `span` (orthographic, along CAMERA_EYE)."""
    eye = np.asarray(CAMERA_EYE, dtype=np.float64)
    d = -eye / np.linalg.norm(eye)
    right = np.cross(d, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, d)
    q = (np.asarray(spots, dtype=np.float64).reshape(-1, 3) - mid) * (FIRST_VIEW_PX / span)
    xs, ys = q @ right, q @ up
    return [(x - CHAR_PX * len(t) / 2 - 3, y - LINE_PX / 2, x + CHAR_PX * len(t) / 2 + 3, y + LINE_PX / 2)
            for x, y, t in zip(xs, ys, texts)]


def stack_names(spots: np.ndarray, texts: list[str], mid: np.ndarray, span: float,
                rank: Optional[list[int]] = None) -> np.ndarray:
    """Spots raised so that no two names print over each other in the first view: by `rank`
    (lower first; default all 0), then from the lowest on the screen up, a name that overlaps
    names already placed goes up (in height, so it stays over its object in every view) to
    just above the highest of them, until it overlaps none."""
    out = np.array(spots, dtype=np.float64).reshape(-1, 3)
    rank = rank or [0] * len(out)
    eye = np.asarray(CAMERA_EYE, dtype=np.float64)
    px_per_m = FIRST_VIEW_PX / span * np.hypot(*eye[:2]) / np.linalg.norm(eye)   # screen y per metre of height
    placed: list[tuple] = []
    for i in sorted(range(len(out)),
                    key=lambda k: (rank[k], screen_boxes(out[k], [texts[k]], mid, span)[0][1], texts[k])):
        box = screen_boxes(out[i], [texts[i]], mid, span)[0]
        for _ in range(len(placed) + 1):
            clash = [b for b in placed if overlaps(box, b)]
            if not clash:
                break
            out[i, 2] += (max(b[3] for b in clash) - box[1]) / px_per_m + 1e-6
            box = screen_boxes(out[i], [texts[i]], mid, span)[0]
        placed.append(box)
    return out


def _name_traces(nodes: list[StoredObject], corners: dict, names: dict, mid: np.ndarray, span: float) -> list:
    """Names over the boxes: the named objects' ("names", shown) and the others' ("other
    names": unnamed objects and structure, legend-only, in grey), stacked where they would
    overlap (the named ones placed first), a raised name joined to its box by a leader line."""
    import plotly.graph_objects as go

    named = [is_named(n) for n in nodes]
    texts = [names[n.id] for n in nodes]
    base = np.array([_name_spot(corners[n.id]) for n in nodes]).reshape(-1, 3)
    tops = stack_names(base, texts, mid, span, rank=[0 if k else 1 for k in named])
    traces = []
    for group, visible, colour in (("names", True, "#111111"), ("other names", "legendonly", "#555555")):
        pick = [i for i, k in enumerate(named) if k == (group == "names")]
        if not pick:
            continue
        traces.append(go.Scatter3d(x=tops[pick, 0], y=tops[pick, 1], z=tops[pick, 2], mode="text", name=group,
                                   text=[texts[i] for i in pick], textfont=dict(size=12, color=colour),
                                   hoverinfo="skip", legendgroup=group, visible=visible))
        raised = [i for i in pick if tops[i, 2] - base[i, 2] > 1e-9]
        if raised:
            under = 0.4 * LINE_PX * span / FIRST_VIEW_PX        # from the box top to under the name
            traces.append(go.Scatter3d(
                x=[v for i in raised for v in (base[i, 0], tops[i, 0], None)],
                y=[v for i in raised for v in (base[i, 1], tops[i, 1], None)],
                z=[v for i in raised for v in (base[i, 2] - 0.03, tops[i, 2] - under, None)],
                mode="lines", line=dict(color="#8a8a8a", width=2), legendgroup=group, showlegend=False,
                hoverinfo="skip", visible=visible, name=f"{group} leaders"))
    return traces


def _relation_traces(edges: list[StoredRelation], nodes: list[StoredObject], corners: dict, names: dict, all_edges: bool) -> list:
    """One trace per stored type (the legend toggles it), a hover point mid-line with the pair's
    merged statements ("cup 1 → dining table: on / smaller than")."""
    import plotly.graph_objects as go

    centre = {n.id: corners[n.id].mean(axis=0) for n in nodes}
    pairs = {(p.s, p.o): p for p in pair_edges(edges)}
    pairs.update({(p.o, p.s): p for p in list(pairs.values())})
    traces = []
    for t in sorted({e.type for e in edges}):
        ex, ey, ez, mx, my, mz, mtext = [], [], [], [], [], [], []
        for e in edges:
            if e.type != t or e.s not in centre or e.o not in centre:
                continue
            a, b = centre[e.s], centre[e.o]
            ex += [a[0], b[0], None]
            ey += [a[1], b[1], None]
            ez += [a[2], b[2], None]
            m = (a + b) / 2
            mx.append(m[0])
            my.append(m[1])
            mz.append(m[2])
            p = pairs.get((e.s, e.o))
            said = p.label if p else word(t)
            s, o = (p.s, p.o) if p else (e.s, e.o)
            mtext.append(f"{htmlmod.escape(names[s])} → {htmlmod.escape(names[o])}: {htmlmod.escape(said)}")
        visible = True if (all_edges or t not in COMPARISON_TYPES) else "legendonly"
        colour = relation_colour(t)
        width, dash = (2, "dot") if t in COMPARISON_TYPES else (3, "dash") if t == "NEAR" else (4, "solid")
        traces.append(go.Scatter3d(x=ex, y=ey, z=ez, mode="lines", name=f"{word(t)} ({len(mx)})",
                                   legendgroup=f"rel-{t}", legend=RELATIONS_LEGEND, visible=visible,
                                   hoverinfo="skip", line=dict(color=colour, width=width, dash=dash)))
        traces.append(go.Scatter3d(x=mx, y=my, z=mz, mode="markers", legendgroup=f"rel-{t}", showlegend=False,
                                   legend=RELATIONS_LEGEND, visible=visible, marker=dict(size=3, color=colour),
                                   hovertext=mtext, hoverinfo="text", name=word(t)))
    return traces


def _room_traces(outlines: dict, corners: dict) -> list:
    """Each room's outline on the floor and its name, where the picture holds more than one room."""
    import plotly.graph_objects as go

    floor = min(c[:, 2].min() for c in corners.values())
    traces = []
    if len(outlines) > 1:
        for r, poly in sorted(outlines.items()):
            traces.append(go.Scatter3d(x=poly[:, 0], y=poly[:, 1], z=np.full(len(poly), floor), mode="lines",
                                       line=dict(color="#555555", width=3, dash="dash"), name=f"room {r}",
                                       legendgroup=f"room-{r}", hoverinfo="skip"))
            c = poly[np.argmax(poly[:, 1])]      # on the outline's far side: the middle holds objects
            traces.append(go.Scatter3d(x=[c[0]], y=[c[1]], z=[floor], mode="text", text=[f"<b>{htmlmod.escape(r)}</b>"],
                                       textfont=dict(size=16, color="#333333"), legendgroup=f"room-{r}",
                                       showlegend=False, hoverinfo="skip"))
    return traces


def _lay_out(fig, lo: np.ndarray, hi: np.ndarray, title: str) -> None:
    """Axes in metres framed on lo..hi (true proportions), the first view from above at an
    angle, two legends as show/hide lists: objects (top right) and relations (bottom right)."""
    span = hi - lo
    axis = dict(dtick=1.0, gridcolor="#d0d0d0", showbackground=True, backgroundcolor="#f7f7f7", zeroline=False)
    legend = dict(x=0.995, xanchor="right", bgcolor="rgba(255,255,255,0.85)", groupclick="togglegroup")
    fig.update_layout(
        title=dict(text=htmlmod.escape(title), x=0.01, y=0.98, font=dict(size=16)),
        autosize=True, margin=dict(l=0, r=0, t=36, b=0), paper_bgcolor="white",
        legend=dict(legend, y=0.98, title=dict(text="<b>objects</b> (click to show / hide)")),
        legend2=dict(legend, y=0.02, yanchor="bottom", title=dict(text="<b>relations</b> (click to show / hide)")),
        scene=dict(xaxis=dict(axis, range=[lo[0], hi[0]], title=dict(text="x (m)")),
                   yaxis=dict(axis, range=[lo[1], hi[1]], title=dict(text="y (m)")),
                   zaxis=dict(axis, range=[lo[2], hi[2]], title=dict(text="up (m)")),
                   aspectmode="manual", aspectratio=dict(x=span[0] / span.max(), y=span[1] / span.max(),
                                                         z=span[2] / span.max()),
                   camera=dict(eye=dict(zip("xyz", CAMERA_EYE)), up=dict(x=0, y=0, z=1)),
                   dragmode="orbit"),
        hoverlabel=dict(bgcolor="white"))


def render_html(scene: Scene, cloud: Optional[tuple] = None, all_edges: bool = False,
                title: str = "scene graph") -> str:
    """The page: plotly.js inline (works offline), the plot filling the window."""
    fig = figure(scene, cloud, all_edges, title)
    div = fig.to_html(full_html=False, include_plotlyjs=True, default_width="100%", default_height="100%",
                      config={"responsive": True, "displaylogo": False, "scrollZoom": True}, div_id="sg3d-view")
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">\n"
            f"<title>{htmlmod.escape(title)}</title>\n"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            "<style>html,body{margin:0;padding:0;width:100%;height:100%;overflow:hidden;"
            "font-family:sans-serif}body>div{width:100%;height:100%}</style>\n</head><body>\n" + div + "\n</body></html>\n")
