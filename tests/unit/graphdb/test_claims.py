"""Rule "stored named boxes claim": an unnamed piece of a stored chair seen by a later scan joins it."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.model import UNNAMED_LABEL, ObjectObservation
from sg3d.graphdb.merge_plan import box_inside_share, claimed_by_stored_box

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
    from sg3d.graphdb.merge_plan import stored_pieces_named

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
    from sg3d.graphdb.merge_plan import stored_pieces_named

    chair = piece((0, 0, 0.4), (0.88, 0.55, 0.8), label="chair")
    blob = {**stored(UNNAMED_LABEL, (-0.1, 0.1, 0.42), (0.8, 0.98, 0.84)), "id": "o-blob"}
    assert box_inside_share((-0.1, 0.1, 0.42), (0.8, 0.98, 0.84), (0, 0, 0.4), (0.88, 0.55, 0.8), BASIS) < 0.5
    assert stored_pieces_named([chair], [blob], {}, {}, BASIS) == {0: 0}


@pytest.mark.parametrize("shift,candidate", [(0.0, True), (0.3, True), (0.55, False)])
def test_pairs_a_stored_box_may_claim_stay_candidates(shift, candidate):
    """The Gaussians of a chair and of its base seen alone lie apart; the claim rules still see them."""
    from sg3d.graphdb.merge_plan import box_claims

    chair = stored("chair", (0, 0, 0.4), (0.6, 0.6, 0.8))
    cup = stored("cup", (0, 0, 0.4), (0.6, 0.6, 0.8))
    base = piece((shift, 0, 0.15), (0.6, 0.6, 0.3))
    assert box_claims([base], [chair, cup], BASIS).tolist() == [[candidate, False]]
    named = piece((shift, 0, 0.4), (0.6, 0.6, 0.8), label="chair")
    blob = stored(UNNAMED_LABEL, (0, 0, 0.15), (0.6, 0.6, 0.3))
    assert box_claims([named], [blob, chair], BASIS).tolist() == [[candidate, False]]
