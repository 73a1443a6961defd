"""Every object in the room: structure, class-agnostic segments and whole-object boxes.

Real frames of the kitchen for the cloud, the structure and the depth existence test; hand-made
boxes for the rules that only need geometry.
"""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.core.model import ObjectObservation
from sg3d.ingest.discover import discovery
from sg3d.ingest.discover.room_cloud import room_cloud
from sg3d.ingest.discover.segments import room_segments
from sg3d.ingest.discover.structure import Element, room_structure, surface_name
from sg3d.ingest.objects.existence import View


def _views(kitchen_dir, indices):
    from sg3d.ingest.poses.gravity import estimate_gravity, sample_frames
    from sg3d.ingest.readers import open_sequence

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
    # a desk boxed from two frames over a third of its top spans the whole top
    desk = _obj("dining table", (0.6, 0.2, 0.60), (0.6, 0.5, 0.40))
    assert discovery.whole_object_box(desk, cloud, [top]) is top
    lo, hi = discovery.gravity_box(desk, cloud)
    assert np.allclose(lo, (-1.0, -0.5, 0.0)) and np.allclose(hi, (1.0, 0.5, 0.73))
    # a chair tucked under that table reaches the floor but keeps its own back's top
    chair = _obj("chair", (0.5, 0.4, 0.70), (0.4, 0.4, 0.30))
    assert discovery.whole_object_box(chair, cloud, [top]) is None
    lo, hi = discovery.gravity_box(chair, cloud)
    assert abs(lo[2]) < 1e-6 and abs(hi[2] - 0.85) < 1e-6
    # a cup is no furniture: its box is what was seen
    cup = _obj("cup", (0.0, 0.0, 0.78), (0.08, 0.08, 0.1))
    assert discovery.whole_object_box(cup, cloud, [top]) is None and cup.size == (0.08, 0.08, 0.1)


def test_flat_pieces_on_the_floor_are_floor_and_a_box_on_it_is_not():
    from sg3d.ingest.discover.segments import Segment

    def seg(lo, hi):
        return Segment(np.zeros((12, 3)), np.array(lo, float), np.array(hi, float), np.arange(6))

    assert discovery.floor_remnant(seg((0, 0, 0.04), (0.9, 0.45, 0.08)))       # 4 cm thick, on the floor
    assert not discovery.floor_remnant(seg((0, 0, 0.04), (0.3, 0.3, 0.25)))    # a box standing there
    assert not discovery.floor_remnant(seg((0, 0, 0.72), (0.3, 0.2, 0.74)))    # papers on a table


def _voxel_block(lo, hi, step=0.025):
    axes = [np.arange(a + step / 2, b, step) for a, b in zip(lo, hi)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def test_two_things_touching_at_a_neck_come_apart_and_one_thing_stays_whole():
    from sg3d.ingest.discover.segments import VOXEL_M, Segment, split_at_necks

    def seg(vox):
        return Segment(vox, vox.min(axis=0) - VOXEL_M / 2, vox.max(axis=0) + VOXEL_M / 2, np.arange(6))

    box = _voxel_block((0.0, 0.0, 0.72), (0.30, 0.25, 0.82))            # a box on a table
    pad = _voxel_block((0.325, 0.10, 0.72), (0.50, 0.225, 0.77))        # a gamepad lying against it
    neck = _voxel_block((0.30, 0.125, 0.72), (0.325, 0.15, 0.745))      # one voxel where they touch
    parts = split_at_necks(seg(np.concatenate([box, neck, pad])))
    assert len(parts) == 2
    sizes = sorted(tuple(np.round(p.size[:2], 3)) for p in parts)
    assert sizes[0][0] <= 0.2 and sizes[1][0] >= 0.3         # the pad and the box, each whole
    assert sum(len(p.voxels) for p in parts) == len(box) + len(neck) + len(pad)
    # one compact thing has no neck: it stays one segment
    assert len(split_at_necks(seg(box))) == 1


def test_a_segment_rests_on_the_surface_under_it_only():
    from sg3d.ingest.discover.segments import Segment

    top = Element("surface", np.array([0.0, 0.0, 0.70]), np.array([1.0, 1.0, 0.72]), 500, 10, height=0.72,
                  footprint=np.ones((20, 20), bool), origin=np.array([0.0, 0.0]))

    def seg(lo, hi):
        return Segment(np.zeros((12, 3)), np.array(lo, float), np.array(hi, float), np.arange(6))

    assert discovery.resting_on(seg((0.2, 0.2, 0.73), (0.4, 0.4, 0.83)), [top])      # a box on the table
    assert not discovery.resting_on(seg((0.2, 0.2, 0.95), (0.4, 0.4, 1.05)), [top])  # floating above it
    assert not discovery.resting_on(seg((1.5, 1.5, 0.73), (1.7, 1.7, 0.83)), [top])  # beside the table


def test_shape_words_and_surface_names():
    assert discovery.shape_word((0.30, 0.22, 0.02)) == "flat"
    assert discovery.shape_word((0.10, 0.10, 0.45)) == "tall"
    assert discovery.shape_word((0.30, 0.25, 0.20)) == "box-shaped"
    assert discovery.shape_word((0.60, 0.10, 0.25)) is None
    assert surface_name(0.9, np.array([0, 0, 0]), np.array([2.0, 0.6, 0])) == "counter"
    assert surface_name(1.5, np.array([0, 0, 0]), np.array([1.5, 0.3, 0])) == "shelf"
    assert surface_name(0.72, np.array([0, 0, 0]), np.array([1.2, 0.7, 0])) == "surface"


def _structure(local_id, label, centre, size):
    from dataclasses import replace

    from tests.factories import obj

    return replace(obj(local_id, label, centre, size=size, var=tuple((np.asarray(size) / 4) ** 2)),
                   layer="structure", hist=np.ones(512))


def test_structure_merges_where_boxes_overlap_and_never_with_objects(store):
    """Two scans of a room with a wall and a cabinet front 0.4 m before it and a floor, the second
    seeing only the wall: the two stay two (one wall's view does not fold the other in), the floor
    is one, and a shelf-top surface never absorbs the book lying on it."""
    from sg3d.graphdb.merge import merge_local_graph
    from tests.factories import graph, obj

    def scan(key, dx, both=True):
        return graph([_structure("w1", "wall", (0.0 + dx, 0.0, 1.0), (0.05, 3.0, 2.0))]
                     + ([_structure("w2", "wall", (0.4 + dx, 0.0, 1.0), (0.05, 3.0, 2.0))] if both else []) + [
                      _structure("f", "floor", (0.75 + dx, 0.0, 0.0), (1.5, 3.0, 0.01)),
                      _structure("s", "shelf", (0.7, 0.0, 1.2 + dx), (0.3, 1.0, 0.03)),
                      obj("b", "book", (0.7, 0.0, 1.23 + dx), size=(0.2, 0.15, 0.03))], key=key)

    merge_local_graph(store, scan("a", 0.0))
    merge_local_graph(store, scan("b", 0.02, both=False))
    _, rows = store.run_raw("MATCH (o:Object) RETURN o.label, o.layer, o.observations", {})
    got = sorted((r[0], r[1], r[2]) for r in rows)
    assert got == [("book", "object", 2), ("floor", "structure", 2), ("shelf", "structure", 2),
                   ("wall", "structure", 1), ("wall", "structure", 2)]
