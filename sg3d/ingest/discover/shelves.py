"""What stands on a bookcase's boards, cut from the bookcase.

A bookcase, a shelving unit or a cabinet open at the front is a frame: sides and a back that rise
the whole height, and boards between them. Things put on a board touch the frame (a book leans on
a side, a box stands against the back), so the voxels of frame and things are one connected
segment and the things vanish into it. Depth tells them apart by physics, not by a room:

- `boards_inside`: a level seen as a horizontal surface inside a segment's height (not its
  floor, not its own top) whose footprint lies mostly within the segment's footprint is one of its
  boards, and a frame has FRAME_MIN_BOARDS of them stacked (a chair's or a couch's seat, a bed's
  top under its headboard are one level inside their furniture, never two);
- `frame_faces`: the frame's sides and back are panels at the ends of its long axis and on its
  side away from the cameras;
- `board_edges`: a board no view saw from above shows its front edge, a layer running the
  frame's whole length;
- `split_frame`: what is left above each board, off the panels and off the boards' own slab, falls into connected pieces; a
  piece of MIN_VOXELS whose bottom rests on a board (`RESTING_M`) is a thing of its own, and the
  rest stays the frame.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy import ndimage

from sg3d.ingest.discover.segments import MIN_VOXELS, RESTING_M, VOXEL_M, Segment
from sg3d.ingest.discover.structure import Element

# A board lies inside a segment's height by at least this (its foot on the floor and its own top
# are not boards between sides) ...
BOARD_INSIDE_M = 0.10
# ... with this share of its footprint inside the segment's footprint.
BOARD_FOOTPRINT_SHARE = 0.5
# Shelving stacks at least this many boards inside its height; seats and beds have one level.
FRAME_MIN_BOARDS = 2
# The frame's sides and back are panels 1.5-2.5 cm thick: their voxels lie within FACE_SLAB_M
# (two voxels: the panel and its depth noise) of the segment's ends along its long axis and of
# its side away from the cameras.
FACE_SLAB_M = 0.05
# ... each sought as the fullest slice within this share of the segment's extent from its end.
PANEL_SEARCH_SHARE = 0.2
# A board seen edge-on (a bookcase's top board at eye height, a board whose top no view saw): a
# layer of voxels off the panels spanning at least BOARD_EDGE_COVER of the frame's length (things
# on a board stand apart, with gaps between them; a board's front edge runs end to end).
BOARD_EDGE_COVER = 0.7
# A board's own slab: its front edge and the voxels that straddle its level, from its
# thickness (2-4 cm) below the level up to it (what lies above it is on it).
BOARD_BELOW_M = 0.05


def board_share(level: float, lo: np.ndarray, hi: np.ndarray, frame_lo: np.ndarray, frame_hi: np.ndarray) -> float:
    """Rule "a board of a frame": the share of a horizontal surface's footprint box (`lo`, `hi`)
    within the frame's footprint when its `level` lies BOARD_INSIDE_M inside the frame's height
    on both sides, else 0; it is one of the frame's boards from BOARD_FOOTPRINT_SHARE on."""
    if not frame_lo[2] + BOARD_INSIDE_M <= level <= frame_hi[2] - BOARD_INSIDE_M:
        return 0.0
    inter = np.clip(np.minimum(frame_hi[:2], hi[:2]) - np.maximum(frame_lo[:2], lo[:2]), 0, None)
    area = float(np.prod(np.maximum(hi[:2] - lo[:2], 1e-3)))
    return float(np.prod(inter)) / area


def boards_inside(seg: Segment, surfaces: Sequence[Element]) -> list[Element]:
    """The horizontal surfaces that are boards of the segment (`board_share`)."""
    return [e for e in surfaces if e.footprint is not None
            and board_share(e.height, e.lo, e.hi, seg.lo, seg.hi) >= BOARD_FOOTPRINT_SHARE]


def frame_of_board(level: float, lo: np.ndarray, hi: np.ndarray,
                   frames: Sequence[tuple[str, np.ndarray, np.ndarray]]) -> str | None:
    """The frame (id, lo, hi) a board found among the room's surfaces belongs to (`board_share`;
    the one holding most of its footprint, the smaller on a tie), None when it is no frame's."""
    shares = [(board_share(level, lo, hi, f_lo, f_hi), -float(np.prod(f_hi[:2] - f_lo[:2])), fid)
              for fid, f_lo, f_hi in frames]
    best = max(shares, default=None)
    return best[2] if best is not None and best[0] >= BOARD_FOOTPRINT_SHARE else None


def _panel_at(x: np.ndarray, lo: float, hi: float) -> float:
    """The voxel cell (centre, m) with the most voxels among those of `x` in [lo, hi]."""
    cells = np.floor(x[(x >= lo) & (x <= hi)] / VOXEL_M).astype(int)
    if not len(cells):
        return lo
    values, counts = np.unique(cells, return_counts=True)
    return float((values[np.argmax(counts)] + 0.5) * VOXEL_M)


def _plan_axes(seg: Segment) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The segment's voxels' (a, b) centre and their coordinates along its long horizontal axis
    and across it (principal axes), with the axes."""
    ab = seg.voxels[:, :2]
    centre = ab.mean(axis=0)
    _, _, axes = np.linalg.svd(ab - centre, full_matrices=False)
    return centre, (ab - centre) @ axes.T, axes


def frame_faces(seg: Segment, toward: np.ndarray) -> np.ndarray:
    """Rule "the frame's panels": per voxel, whether it lies within FACE_SLAB_M of a panel: the
    fullest voxel slice in the outer PANEL_SEARCH_SHARE of the segment's long horizontal axis at
    each end (the sides; a panel is a dense sheet, depth noise around it a sparse fringe) and on
    its long side away from `toward` (the cameras' mean (a, b): the back)."""
    centre, st, axes = _plan_axes(seg)
    s, t = st[:, 0], st[:, 1]
    reach_s = PANEL_SEARCH_SHARE * float(np.ptp(s))
    reach_t = PANEL_SEARCH_SHARE * float(np.ptp(t))
    sides = (_panel_at(s, s.min(), s.min() + reach_s), _panel_at(s, s.max() - reach_s, s.max()))
    if float((np.asarray(toward, float) - centre) @ axes[1]) < 0:
        back = _panel_at(t, t.max() - reach_t, t.max())
    else:
        back = _panel_at(t, t.min(), t.min() + reach_t)
    return ((np.abs(s - sides[0]) <= FACE_SLAB_M) | (np.abs(s - sides[1]) <= FACE_SLAB_M)
            | (np.abs(t - back) <= FACE_SLAB_M))


def board_edges(seg: Segment, faces: np.ndarray) -> list[float]:
    """Rule "a board seen edge-on": the levels (the top of each run of consecutive voxel layers)
    where the voxels off the panels cover BOARD_EDGE_COVER of the frame's long axis."""
    s = _plan_axes(seg)[1][:, 0]
    along = np.floor((s - s.min()) / VOXEL_M).astype(int)
    layer = np.floor((seg.voxels[:, 2] - seg.lo[2]) / VOXEL_M).astype(int)
    cells = np.unique(np.c_[layer[~faces], along[~faces]], axis=0)
    cover = np.bincount(cells[:, 0], minlength=int(layer.max()) + 1) / (int(along.max()) + 1)
    edge = cover >= BOARD_EDGE_COVER
    return [float(seg.lo[2]) + (k + 1) * VOXEL_M for k in np.flatnonzero(edge) if k + 1 >= len(edge) or not edge[k + 1]]


def split_frame(seg: Segment, surfaces: Sequence[Element], toward: np.ndarray) -> list[Segment]:
    """Rule "what stands on a board is not the bookcase": a segment with FRAME_MIN_BOARDS boards
    inside it (`boards_inside`) loses the voxels off its panels (`frame_faces`, `toward`: the
    cameras' mean (a, b)) that lie above a board's slab; a board seen edge-on (`board_edges`) is
    a board too. Those voxels fall into connected pieces (26-neighbourhood), and each piece of
    MIN_VOXELS whose bottom rests on a board is a segment of its own. The frame keeps the rest.
    The segment is returned whole when it has too few boards or no piece comes off. Parts carry
    no depth evidence yet (`segments.depth_evidence`)."""
    boards = boards_inside(seg, surfaces)
    if len(boards) < FRAME_MIN_BOARDS:
        return [seg]
    faces = frame_faces(seg, toward)
    z = seg.voxels[:, 2]
    levels = np.array([e.height for e in boards] + board_edges(seg, faces))
    on_board = np.zeros(len(z), bool)
    for level in levels:
        on_board |= (z >= level - BOARD_BELOW_M) & (z <= level)
    loose = ~faces & ~on_board & (z > levels.min())
    if not loose.any():
        return [seg]
    ijk = np.floor((seg.voxels - seg.lo) / VOXEL_M).astype(int)
    grid = np.zeros(ijk.max(axis=0) + 1, bool)
    grid[tuple(ijk[loose].T)] = True
    labels, n = ndimage.label(grid, structure=np.ones((3, 3, 3), bool))
    own = np.where(loose, labels[tuple(ijk.T)], 0)
    parts, taken = [], np.zeros(len(z), bool)
    for c in range(1, n + 1):
        member = own == c
        if member.sum() < MIN_VOXELS:
            continue
        vox = seg.voxels[member]
        bottom = float(vox[:, 2].min()) - VOXEL_M / 2
        if float(np.min(np.abs(levels - bottom))) > RESTING_M:
            continue
        parts.append(Segment(vox, vox.min(axis=0) - VOXEL_M / 2, vox.max(axis=0) + VOXEL_M / 2, seg.frames,
                             on_board=True))
        taken |= member
    if not parts:
        return [seg]
    rest = seg.voxels[~taken]
    frame = Segment(rest, rest.min(axis=0) - VOXEL_M / 2, rest.max(axis=0) + VOXEL_M / 2, seg.frames)
    return [frame] + parts
