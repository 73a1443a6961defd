"""Node ids from what a merge knows (`sg3d.merge.ids`): the same inputs name the same node on any
machine, and any other room, revision or index names another."""
from __future__ import annotations

import itertools
import re

from sg3d.merge.ids import ID_HEX_DIGITS, MergeIds


def test_an_id_is_the_hash_of_room_revision_and_index_and_never_changes():
    # pinned (SHA-256: no hash seed, no machine in it): a change of the rule renames the nodes every
    # later build makes, and two versions would build different graphs of the same frames
    ids = MergeIds("home/kitchen", 3)
    assert (ids.object_id(0), ids.object_id(1), ids.scan_id()) == ("o-9a7eeebf46916d0b", "o-5ee597504cbc0259",
                                                                   "merge-9941e82bcc3e")
    assert ID_HEX_DIGITS == 16
    assert re.fullmatch(r"o-[0-9a-f]{16}", ids.object_id(7))


def test_another_room_revision_or_index_gives_another_id():
    made = [MergeIds(room, rev).object_id(i)
            for room, rev, i in itertools.product(("home/kitchen", "home/kitchen2", "home2/kitchen"), range(1, 30),
                                                  range(40))]
    assert len(set(made)) == len(made)
    # the parts are kept apart: ("a/b", 12, 3) is not ("a/b1", 2, 3)
    assert MergeIds("a/b", 12).object_id(3) != MergeIds("a/b1", 2).object_id(3)
    assert MergeIds("a/b", 1).scan_id() != MergeIds("a/b", 2).scan_id()

