"""Rule "stored named boxes claim": an unnamed piece of a stored chair seen by a later scan joins it."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.model import UNNAMED_LABEL, ObjectObservation
from sg3d.merge.plan import box_inside_share, claimed_by_stored_box

BASIS = np.eye(3)


def piece(centre, size, label=UNNAMED_LABEL, layer="object") -> ObjectObservation:
    return ObjectObservation("u0", [label], [0.5], tuple(centre), (0.01, 0.01, 0.01), 10, tuple(size),
                             np.ones(512), box_centre=tuple(centre), layer=layer)


def stored(label, centre, size, layer="object") -> dict:
    return {"id": f"o-{label}", "label": label, "layer": layer, "box_centre": list(centre),
            "x": centre[0], "y": centre[1], "z": centre[2], "size": list(size)}


def test_inside_share_is_the_share_of_the_first_box_inside_the_second():
    assert box_inside_share((0, 0, 0), (1, 1, 1), (0, 0, 0), (2, 2, 2), BASIS) == pytest.approx(1.0)
    assert box_inside_share((0.5, 0, 0), (1, 1, 1), (0, 0, 0), (1, 1, 1), BASIS) == pytest.approx(0.5)
    assert box_inside_share((3, 0, 0), (1, 1, 1), (0, 0, 0), (1, 1, 1), BASIS) == 0.0


@pytest.mark.parametrize("shift,claimed", [(0.0, True), (0.3, True), (0.55, False)])
def test_a_chairs_base_inside_the_stored_chair_is_claimed(shift, claimed):
    chair = stored("chair", (0, 0, 0.4), (0.6, 0.6, 0.8))
    base = piece((shift, 0, 0.15), (0.6, 0.6, 0.3))       # inside share = 1 - shift / 0.6
    assert (claimed_by_stored_box(base, [chair], BASIS) == "o-chair") is claimed


def test_only_unnamed_objects_and_only_by_floor_standing_named_objects():
    chair = stored("chair", (0, 0, 0.4), (0.6, 0.6, 0.8))
    cup = stored("cup", (0, 0, 0.4), (0.6, 0.6, 0.8))
    wall = stored("chair", (0, 0, 0.4), (0.6, 0.6, 0.8), layer="structure")
    inside = ((0, 0, 0.2), (0.3, 0.3, 0.3))
    assert claimed_by_stored_box(piece(*inside), [cup, wall], BASIS) is None
    assert claimed_by_stored_box(piece(*inside, label="book"), [chair], BASIS) is None
    assert claimed_by_stored_box(piece(*inside, layer="structure"), [chair], BASIS) is None


def test_a_new_chair_takes_over_the_stored_piece_inside_its_box():
    from sg3d.merge.plan import stored_pieces_named

    chair = piece((0, 0, 0.4), (0.6, 0.6, 0.8), label="chair")
    base = {**stored(UNNAMED_LABEL, (0, 0, 0.15), (0.5, 0.5, 0.3)), "id": "o-base"}
    far = {**stored(UNNAMED_LABEL, (2, 0, 0.15), (0.5, 0.5, 0.3)), "id": "o-far"}
    cup = piece((0, 0, 0.9), (0.1, 0.1, 0.1), label="cup")
    assert stored_pieces_named([chair, cup], [far, base], {}, {}, BASIS) == {0: 1}
    assert stored_pieces_named([chair], [base], {0: 0}, {}, BASIS) == {}          # matched already
    assert stored_pieces_named([chair], [base], {}, {0: 5}, BASIS) == {}          # folded elsewhere


def test_a_new_chair_takes_over_a_stored_blob_wider_than_its_box():
    """The earlier scan saw the chair as an unnamed blob with its base spread wider than the chair's
    box: the overlap is judged on the smaller box (`box_overlap_share`)."""
    from sg3d.merge.plan import stored_pieces_named

    chair = piece((0, 0, 0.4), (0.88, 0.55, 0.8), label="chair")
    blob = {**stored(UNNAMED_LABEL, (-0.1, 0.1, 0.42), (0.8, 0.98, 0.84)), "id": "o-blob"}
    assert box_inside_share((-0.1, 0.1, 0.42), (0.8, 0.98, 0.84), (0, 0, 0.4), (0.88, 0.55, 0.8), BASIS) < 0.5
    assert stored_pieces_named([chair], [blob], {}, {}, BASIS) == {0: 0}


@pytest.mark.parametrize("shift,candidate", [(0.0, True), (0.3, True), (0.55, False)])
def test_pairs_a_stored_box_may_claim_stay_candidates(shift, candidate):
    """The Gaussians of a chair and of its base seen alone lie apart; the claim rules still see them."""
    from sg3d.merge.plan import box_claims

    chair = stored("chair", (0, 0, 0.4), (0.6, 0.6, 0.8))
    cup = stored("cup", (0, 0, 0.4), (0.6, 0.6, 0.8))
    base = piece((shift, 0, 0.15), (0.6, 0.6, 0.3))
    assert box_claims([base], [chair, cup], BASIS).tolist() == [[candidate, False]]
    named = piece((shift, 0, 0.4), (0.6, 0.6, 0.8), label="chair")
    blob = stored(UNNAMED_LABEL, (0, 0, 0.15), (0.6, 0.6, 0.3))
    assert box_claims([named], [blob, chair], BASIS).tolist() == [[candidate, False]]


# --- a carrel's panel beside a STORED desk (`claimed_by_stored_desk`) ------------------------------

DESK = stored("desk", (0.5, 0.35, 0.35), (1.0, 0.7, 0.7))        # from the floor (0) to its top (0.7)


@pytest.mark.parametrize("gap,claimed", [(0.05, True), (0.35, True), (0.45, False)])
def test_a_panel_before_a_stored_desk_is_that_desk(gap, claimed):     # CARREL_REACH_M
    from sg3d.merge.plan import box_claims, claimed_by_stored_desk

    panel = piece((0.6, 0.7 + gap + 0.15, 0.7), (0.15, 0.3, 1.4))     # 0.15 thick, up to 1.4 m
    assert (claimed_by_stored_desk(panel, [DESK], BASIS) == "o-desk") is claimed
    assert box_claims([panel], [DESK], BASIS).tolist() == [[claimed]]


@pytest.mark.parametrize("thickness,claimed", [(0.20, True), (0.25, False)])
def test_a_stored_desks_panel_is_thin(thickness, claimed):            # CARREL_PANEL_MAX_THICKNESS_M
    from sg3d.merge.plan import claimed_by_stored_desk

    panel = piece((1.1, 0.35, 0.7), (thickness, 0.6, 1.4))           # beside the desk's end
    assert (claimed_by_stored_desk(panel, [DESK], BASIS) == "o-desk") is claimed


def test_only_unnamed_pieces_rising_above_a_stored_desk_are_its_panels():
    from sg3d.merge.plan import claimed_by_stored_desk

    low = piece((1.1, 0.35, 0.3), (0.15, 0.6, 0.6))                  # tops out under the desk top
    named = piece((1.1, 0.35, 0.7), (0.15, 0.6, 1.4), label="book")
    panel = piece((1.1, 0.35, 0.7), (0.15, 0.6, 1.4))
    table = stored("dining table", (0.5, 0.35, 0.35), (1.0, 0.7, 0.7))
    assert claimed_by_stored_desk(low, [DESK], BASIS) is None
    assert claimed_by_stored_desk(named, [DESK], BASIS) is None
    assert claimed_by_stored_desk(panel, [table], BASIS) is None


# --- a solid kind read over a stored shape-named desk (`desk_named_solid`) -------------------------

SHAPE_DESK = {**DESK, "named_by": "shape"}


@pytest.mark.parametrize("shift,claimed", [(0.0, True), (0.55, True), (0.65, False)])
def test_a_refrigerator_holding_half_a_stored_desk_is_that_desk(shift, claimed):   # CLAIM_SHARE
    from sg3d.merge.plan import desk_named_solid

    # the desk spans a 0..1; the refrigerator's box a shift-0.1 .. shift+0.9: it holds 1.1 - shift of it
    fridge = piece((0.4 + shift, 0.35, 0.6), (1.0, 1.1, 1.2), label="refrigerator")
    assert (desk_named_solid(fridge, [SHAPE_DESK], BASIS) == "o-desk") is claimed


def test_only_solid_kinds_over_a_desk_named_by_its_shape():
    from sg3d.merge.plan import desk_named_solid

    over = ((0.5, 0.35, 0.6), (1.2, 1.1, 1.2))
    assert desk_named_solid(piece(*over, label="oven"), [SHAPE_DESK], BASIS) == "o-desk"
    assert desk_named_solid(piece(*over, label="chair"), [SHAPE_DESK], BASIS) is None      # open below
    assert desk_named_solid(piece(*over, label="refrigerator"), [DESK], BASIS) is None     # no shape evidence
    assert desk_named_solid(piece(*over), [SHAPE_DESK], BASIS) is None
