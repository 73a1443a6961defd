"""Ingest steps on the real 7-Scenes kitchen: the reader opens it with its intrinsics, frame
selection keeps a small share, gravity is perpendicular to the table, and the existence test keeps
what the detector keeps finding while rejecting a detection one frame made up."""
from __future__ import annotations

import numpy as np
import pytest

from sg3d.ingest.detect.models import Detection
from sg3d.ingest.objects import existence, fusion
from sg3d.ingest.objects.attributes import world_points
from sg3d.ingest.poses.gravity import estimate_gravity, estimate_up, sample_frames
from sg3d.ingest.readers import open_sequence
from sg3d.ingest.select.selection import select_frames


def test_kitchen_opens_with_its_intrinsics(kitchen_dir):
    seq = open_sequence(kitchen_dir)
    assert seq.layout == "7scenes" and len(seq) == 1000 and seq.image_size == (640, 480)
    f = seq.frame(0)
    assert f.depth.shape == (480, 640) and 0.5 < float(np.median(f.depth[f.depth > 0])) < 5.0


def test_kitchen_keeps_at_most_15_percent(kitchen_dir):
    seq = open_sequence(kitchen_dir)
    groups, stats = select_frames(seq)
    assert stats.read == 1000 and stats.skipped == 0
    assert 0 < stats.blurry < 300
    assert stats.groups == len(groups) >= 2
    assert 0 < stats.fraction_kept <= 0.15
    assert sum(len(g) for g in groups) == stats.kept
    for g in groups:
        assert all(f.is_loaded for f in g.frames)  # ready for detection
        assert [f.index for f in g.frames] == sorted(f.index for f in g.frames)


def test_up_is_perpendicular_to_the_kitchen_table(kitchen_dir):
    seq = open_sequence(kitchen_dir)
    gravity = estimate_gravity(sample_frames(seq, 12))
    up = np.asarray(gravity.up)
    assert np.linalg.norm(up) == pytest.approx(1.0)
    np.testing.assert_allclose(estimate_up(sample_frames(seq, 12)), up)
    # a patch of the table top in frame 1 (chosen by looking at the image): fit its plane here
    f = seq.frame(1)
    x1, y1, x2, y2 = 300, 240, 420, 320
    d = f.depth[y1:y2, x1:x2]
    v, u = np.nonzero(d > 0)
    pts = world_points(u + float(x1), v + float(y1), d[v, u].astype(float), f.K, f.pose)
    centred = pts - pts.mean(axis=0)
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    assert sv[2] / np.sqrt(len(pts)) < 0.02          # it is a plane (rms off-plane < 2 cm)
    angle = np.degrees(np.arccos(abs(vt[2] @ up)))
    assert angle < 5.0
    # up points against gravity: cameras are held upright, their image-up agrees
    assert np.mean([(-g.pose[:3, 1]) @ up > 0 for g in sample_frames(seq, 12)]) > 0.9
    # the table top lies well above the floor, below the cameras
    assert gravity.floor_height is not None
    table = float(pts.mean(axis=0) @ up) - gravity.floor_height
    assert 0.5 < table < 1.1


@pytest.fixture(scope="module")
def kitchen_views(kitchen_dir):
    """Twelve real frames of the kitchen's first second (the table and chairs in view)."""
    from sg3d.ingest.readers import open_sequence

    seq = open_sequence(kitchen_dir)
    return [seq.frame(i) for i in range(0, 120, 10)]


def _centre_point(frame, u: int, v: int):
    d = float(frame.depth[v, u])
    K = frame.K
    cam = np.array([(u - K[0, 2]) / K[0, 0] * d, (v - K[1, 2]) / K[1, 1] * d, d])
    return frame.pose[:3, :3] @ cam + frame.pose[:3, 3], d


def test_visibility_on_real_frames_sees_inside_and_knows_occlusion(kitchen_views):
    frame = kitchen_views[0]
    view = existence.View.of(frame)
    v, u = np.argwhere(frame.depth[200:280, 280:360] > 0)[0] + (200, 280)
    point, d = _centre_point(frame, int(u), int(v))
    assert existence.expected_in_view(point, 0.3, view) > 0
    behind = point + (point - frame.pose[:3, 3]) / d * 1.5   # 1.5 m further along the same ray
    assert existence.expected_in_view(behind, 0.3, view) == 0.0
    assert existence.expected_in_view(frame.pose[:3, 3] - 2 * frame.pose[:3, 2], 0.3, view) == 0.0  # behind the camera


def test_existence_keeps_what_the_detector_keeps_finding_and_rejects_a_made_up_detection(kitchen_views):
    from sg3d.ingest.detect.models import SsdMobilenetDetector
    from sg3d.ingest.objects.attributes import measure_object
    from sg3d.ingest.poses.gravity import estimate_gravity

    up = estimate_gravity(kitchen_views).up
    detector = SsdMobilenetDetector()
    sightings, views = [], []
    for frame in kitchen_views:
        for det in detector.detect(frame.color):
            attrs = measure_object(frame, det.box, up)
            if attrs is not None:
                sightings.append(fusion.Sighting.of(frame.index, det, attrs, np.eye(3)))
        views.append(existence.View.of(frame))
    # a "tv" the detector never said, in one frame, on the middle of the table
    fake_frame = kitchen_views[4]
    fake = Detection((300, 260, 360, 300), ["tv"], [0.9])
    made_up = fusion.Sighting.of(fake_frame.index, fake, measure_object(fake_frame, fake.box, up), np.eye(3))
    sightings.append(made_up)

    hyps = fusion.consolidate(fusion.associate(sightings))
    verdict = {}
    for h in hyps:
        ev = existence.evidence((h.lo + h.hi) / 2, h.extent, set(h.frames), views)
        verdict.setdefault(h.label, []).append((existence.exists(ev), ev))
        if any(s is made_up for s in h.sightings):
            assert h.sightings == [made_up] and not existence.exists(ev) and ev.expected > 1
    kept = [(label, ev) for label, v in verdict.items() for ok, ev in v if ok]
    assert {"dining table", "chair"} <= {label for label, _ in kept}
    assert all(ev.detected >= 0.5 * ev.expected for label, ev in kept if label == "dining table")
