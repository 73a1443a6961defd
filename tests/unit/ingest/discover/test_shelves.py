"""What stands on a bookcase's boards comes off the bookcase (`shelves`): a voxel bookcase with
two boards, things on them, and each threshold on both sides."""
from __future__ import annotations

import numpy as np

from sg3d.ingest.discover import shelves
from sg3d.ingest.discover.segments import VOXEL_M, Segment
from sg3d.ingest.discover.structure import SURFACE_CELL_M, Element

CAMERAS = np.array([0.5, -2.0])       # in front of the case (its front at b = 0, its back at b = 0.3)
BOARDS = (0.4, 0.8)


def _block(lo, hi) -> np.ndarray:
    axes = [np.arange(a + VOXEL_M / 2, b - 1e-9, VOXEL_M) for a, b in zip(lo, hi)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def _board(height: float, x0: float = 0.0, x1: float = 1.0) -> Element:
    cells = (int(round((x1 - x0) / SURFACE_CELL_M)), int(round(0.3 / SURFACE_CELL_M)))
    return Element("shelf", np.array([x0, 0.0, height - 0.03]), np.array([x1, 0.3, height]), 100, 5, height,
                   np.ones(cells, bool), np.array([x0, 0.0]))


def _case(*things, boards=BOARDS, height=1.2, edges=True) -> Segment:
    """Sides at a = 0 and a = 1, a back at b = 0.3, each board's front edge (a voxel under its
    level), and `things` (lo, hi) boxes."""
    parts = [_block((0, 0, 0), (0.025, 0.3, height)), _block((0.975, 0, 0), (1.0, 0.3, height)),
             _block((0, 0.275, 0), (1.0, 0.3, height))]
    if edges:
        parts += [_block((0, 0, b - VOXEL_M), (1.0, 0.025, b)) for b in boards]
    parts += [_block(lo, hi) for lo, hi in things]
    v = np.unique(np.round(np.concatenate(parts), 4), axis=0)
    return Segment(v, v.min(axis=0) - VOXEL_M / 2, v.max(axis=0) + VOXEL_M / 2, np.arange(8))


BOX = ((0.30, 0.05, BOARDS[0]), (0.50, 0.20, BOARDS[0] + 0.15))
CUP = ((0.60, 0.10, BOARDS[1]), (0.70, 0.20, BOARDS[1] + 0.10))


def _parts(seg, boards=BOARDS):
    return shelves.split_frame(seg, [_board(b) for b in boards], CAMERAS)


def test_the_things_on_two_boards_come_off_the_case_and_the_case_stays():
    frame, *things = _parts(_case(BOX, CUP))
    assert len(things) == 2 and all(t.on_board for t in things)
    boxes = sorted((np.round(t.lo, 2).tolist(), np.round(t.hi, 2).tolist()) for t in things)
    assert boxes == [([0.3, 0.05, 0.4], [0.5, 0.2, 0.55]), ([0.6, 0.1, 0.8], [0.7, 0.2, 0.9])]
    assert frame.size[2] > 1.1 and not frame.on_board


def test_a_case_needs_two_boards_inside_it():                         # FRAME_MIN_BOARDS
    assert len(_parts(_case(BOX, CUP))) == 3
    assert len(_parts(_case(BOX, CUP), boards=BOARDS[:1])) == 1


def test_a_board_lies_10_cm_inside_the_segments_height():             # BOARD_INSIDE_M
    seg = _case(BOX)                                                    # from 0 to 1.2 m
    assert len(shelves.boards_inside(seg, [_board(0.11), _board(1.09)])) == 2
    assert shelves.boards_inside(seg, [_board(0.09), _board(1.11)]) == []


def test_a_board_lies_half_within_the_segments_footprint():           # BOARD_FOOTPRINT_SHARE
    seg = _case(BOX)                                                    # a from 0 to 1
    assert len(shelves.boards_inside(seg, [_board(0.5, 0.45, 1.45)])) == 1
    assert shelves.boards_inside(seg, [_board(0.5, 0.55, 1.55)]) == []


def test_a_piece_resting_within_5_cm_of_a_board_comes_off():          # RESTING_M
    lift = 0.0375                                                       # its bottom 3.75 cm over the board
    near = ((0.30, 0.05, BOARDS[0] + lift), (0.50, 0.20, BOARDS[0] + 0.15))
    assert len(_parts(_case(near))) == 2
    lift = 0.0625
    far = ((0.30, 0.05, BOARDS[0] + lift), (0.50, 0.20, BOARDS[0] + 0.15))
    assert len(_parts(_case(far))) == 1


def test_a_thing_against_a_side_panel_stays_with_it_and_one_clear_of_it_comes_off():   # FACE_SLAB_M
    # the side's voxels are centred at a = 0.0125; a slice 2.5 cm from it is the panel's, one
    # 7.5 cm from it is a thing's
    touching = ((0.025, 0.05, BOARDS[0]), (0.05, 0.20, BOARDS[0] + 0.15))
    clear = ((0.075, 0.05, BOARDS[0]), (0.10, 0.20, BOARDS[0] + 0.15))
    assert len(_parts(_case(clear))) == 2
    assert len(_parts(_case(touching))) == 1


def test_the_panels_are_the_fullest_slices_not_the_noise_beyond_them():   # PANEL_SEARCH_SHARE
    fringe = ((-0.10, 0.10, 0.60), (-0.075, 0.125, 0.625))              # a flying pixel 8 cm outside
    seg = _case(BOX, CUP, fringe)
    faces = shelves.frame_faces(seg, CAMERAS)
    side = (seg.voxels[:, 0] < 0.025) & (seg.voxels[:, 0] > 0)
    assert faces[side].all()


def test_a_board_seen_only_edge_on_is_found_by_its_edge():            # BOARD_EDGE_COVER
    seg = _case(BOX, CUP, ((0.2, 0.1, 1.0), (0.4, 0.2, 1.1)), boards=(0.4, 0.8, 1.0))
    assert any(abs(level - 1.0) < 0.02 for level in shelves.board_edges(seg, shelves.frame_faces(seg, CAMERAS)))
    things = _parts(seg)[1:]                                             # the level at 1.0 m is no surface
    assert any(abs(t.lo[2] - 1.0) < 0.02 for t in things)


def test_an_edge_covers_70_percent_of_the_case():                      # BOARD_EDGE_COVER
    def levels(x1):
        seg = _case(BOX, CUP, ((0.0, 0.0, 1.0 - VOXEL_M), (x1, 0.025, 1.0)))
        return shelves.board_edges(seg, shelves.frame_faces(seg, CAMERAS))
    assert any(abs(v - 1.0) < 0.02 for v in levels(0.80))             # 0.75 of the case's 0.95 inside
    assert not any(abs(v - 1.0) < 0.02 for v in levels(0.65))


def _frame(fid: str, lo, hi) -> tuple[str, np.ndarray, np.ndarray]:
    return fid, np.asarray(lo, float), np.asarray(hi, float)


def test_a_board_among_the_rooms_surfaces_belongs_to_the_frame_around_it():   # frame_of_board
    case = _frame("case", (0, 0, 0), (1.0, 0.35, 1.4))
    board_lo, board_hi = np.array([0.05, 0.02, 0.42]), np.array([0.95, 0.33, 0.45])
    assert shelves.frame_of_board(0.45, board_lo, board_hi, [case]) == "case"
    # BOARD_INSIDE_M: a level 10 cm inside the frame's height is a board, 9 cm is its foot or top
    assert shelves.frame_of_board(0.10, board_lo, board_hi, [case]) == "case"
    assert shelves.frame_of_board(0.09, board_lo, board_hi, [case]) is None
    assert shelves.frame_of_board(1.29, board_lo, board_hi, [case]) == "case"
    assert shelves.frame_of_board(1.31, board_lo, board_hi, [case]) is None
    # BOARD_FOOTPRINT_SHARE: half the board's footprint within the frame's, not less
    half = _frame("half", (0.5, 0, 0), (1.5, 0.35, 1.4))
    assert shelves.frame_of_board(0.45, np.array([0.0, 0.0, 0.42]), np.array([1.0, 0.3, 0.45]), [half]) == "half"
    less = _frame("less", (0.51, 0, 0), (1.5, 0.35, 1.4))
    assert shelves.frame_of_board(0.45, np.array([0.0, 0.0, 0.42]), np.array([1.0, 0.3, 0.45]), [less]) is None


def test_a_board_goes_to_the_frame_holding_most_of_it():
    board_lo, board_hi = np.array([0.0, 0.0, 0.42]), np.array([1.0, 0.3, 0.45])
    most = _frame("most", (0.0, 0, 0), (0.9, 0.35, 1.4))
    some = _frame("some", (0.3, 0, 0), (1.2, 0.35, 1.4))
    assert shelves.frame_of_board(0.45, board_lo, board_hi, [some, most]) == "most"
    assert shelves.frame_of_board(0.45, board_lo, board_hi, []) is None
