"""Every object in the room: structure, class-agnostic segments and whole-object boxes.

Real frames of the kitchen for the cloud, the structure and the depth existence test; hand-made
boxes for the rules that only need geometry.
"""
from __future__ import annotations

import numpy as np
import pytest

from ingest import discovery
from ingest.existence import View
from ingest.model import ObjectObservation
from ingest.room_cloud import room_cloud
from ingest.segments import room_segments
from ingest.structure import Element, room_structure, surface_name


def _views(kitchen_dir, indices):
    from ingest.gravity import estimate_gravity, sample_frames
    from ingest.readers import open_sequence

    seq = open_sequence(kitchen_dir)
    gravity = estimate_gravity(sample_frames(seq, 20))
    return [View.of(seq.frame(i)) for i in indices], gravity


@pytest.fixture(scope="module")
def kitchen_views(kitchen_dir):
    return _views(kitchen_dir, range(0, 400, 8))


def test_the_kitchen_cloud_has_a_floor_a_wall_and_the_table_top(kitchen_views):
    views, gravity = kitchen_views
    cloud = room_cloud(views, gravity.up, gravity.floor_height)
    structure = room_structure(cloud)
    labels = [e.label for e in structure]
    assert labels.count("floor") == 1
    assert "wall" in labels
    # the dining table's top: a broad horizontal surface about 0.7 m above the floor
    tops = [e for e in structure if e.footprint is not None and 0.6 <= e.height <= 0.8
            and min(e.hi[:2] - e.lo[:2]) > 0.6]
    assert tops, [(e.label, round(e.height, 2)) for e in structure]


def test_a_blob_seen_in_one_frame_only_is_no_object(kitchen_views):
    """An artefact in one frame's depth (a patch 0.9 m in front of the camera, in mid-air) is
    seen through by every other view of that place: no segment is kept there, while the real
    objects of the same frames are."""
    views, gravity = kitchen_views
    k = len(views) // 2
    fake = views[k].depth.copy()
    h, w = fake.shape
    fake[h // 2 - 6:h // 2 + 6, w // 2 - 6:w // 2 + 6] = 0.9
    bad = list(views)
    bad[k] = View(views[k].index, views[k].K, views[k].pose, views[k].size, fake)
    cloud = room_cloud(bad, gravity.up, gravity.floor_height)
    segments = room_segments(cloud, room_structure(cloud))
    assert len(segments) >= 5
    # where the blob floats, in world coordinates
    K, pose = views[k].K, views[k].pose
    ray = np.array([(views[k].size[0] / 2 - K[0, 2]) / K[0, 0], (views[k].size[1] / 2 - K[1, 2]) / K[1, 1], 1.0])
    blob = pose[:3, :3] @ (ray * 0.9) + pose[:3, 3]
    centres = [cloud.to_world((s.lo + s.hi) / 2) for s in segments]
    assert min(float(np.linalg.norm(c - blob)) for c in centres) > 0.2


def _cloud_stub(floor=0.0):
    class Stub:
        basis = np.eye(3)

        def __init__(self):
            self.floor = floor

        def to_world(self, local):
            q = np.array(local, float)
            q[..., 2] += self.floor
            return q @ self.basis
    return Stub()


def _obj(label, centre, size):
    return ObjectObservation(local_id=label, labels=[label], scores=[0.8], mean=tuple(centre), var=(0.01,) * 3,
                             n_points=100, size=tuple(size), hist=np.ones(512), box_centre=tuple(centre))


def test_a_table_box_reaches_the_floor_and_ends_at_its_own_top():
    """The detector boxed a table's top slab (8 cm) and what stands on it made it 20 cm; its
    whole box runs from the floor to the surface it owns."""
    cloud = _cloud_stub()
    top = Element("surface", np.array([-1.0, -0.5, 0.70]), np.array([1.0, 0.5, 0.73]), 1000, 20, height=0.73,
                  footprint=np.ones((40, 20), bool), origin=np.array([-1.0, -0.5]))
    table = _obj("dining table", (0.0, 0.0, 0.80), (1.8, 1.0, 0.20))
    assert discovery.whole_object_box(table, cloud, [top]) is top
    lo, hi = discovery.gravity_box(table, cloud)
    assert abs(lo[2]) < 1e-6 and abs(hi[2] - 0.73) < 1e-6
    # a chair tucked under that table reaches the floor but keeps its own back's top
    chair = _obj("chair", (0.5, 0.4, 0.70), (0.4, 0.4, 0.30))
    assert discovery.whole_object_box(chair, cloud, [top]) is None
    lo, hi = discovery.gravity_box(chair, cloud)
    assert abs(lo[2]) < 1e-6 and abs(hi[2] - 0.85) < 1e-6
    # a cup is no furniture: its box is what was seen
    cup = _obj("cup", (0.0, 0.0, 0.78), (0.08, 0.08, 0.1))
    assert discovery.whole_object_box(cup, cloud, [top]) is None and cup.size == (0.08, 0.08, 0.1)


def test_shape_words_and_surface_names():
    assert discovery.shape_word((0.30, 0.22, 0.02)) == "flat"
    assert discovery.shape_word((0.10, 0.10, 0.45)) == "tall"
    assert discovery.shape_word((0.30, 0.25, 0.20)) == "box-shaped"
    assert discovery.shape_word((0.60, 0.10, 0.25)) is None
    assert surface_name(0.9, np.array([0, 0, 0]), np.array([2.0, 0.6, 0])) == "counter"
    assert surface_name(1.5, np.array([0, 0, 0]), np.array([1.5, 0.3, 0])) == "shelf"
    assert surface_name(0.72, np.array([0, 0, 0]), np.array([1.2, 0.7, 0])) == "surface"
