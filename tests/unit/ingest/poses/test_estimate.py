"""Pose estimation's decisions (`sg3d.ingest.poses.estimate`): tracking, keyframes, loop closures and
segment links, with a stand-in odometry that knows the true camera path and reports, for each fit,
the measurements a scene script gives it (the real odometry on rendered depth: tests/e2e/test_poses.py)."""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.ingest.poses import estimate
from sg3d.ingest.poses.tracking import Fit, View
from sg3d.ingest.readers.frames import FrameError

K = np.array([[100.0, 0, 79.5], [0, 100.0, 59.5], [0, 0, 1]])


def pose(x: float = 0.0, y: float = 0.0, yaw_deg: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("y", yaw_deg, degrees=True).as_matrix()
    T[:3, 3] = (x, y, 0.0)
    return T


class Scene:
    """The true poses, the frames that cannot be read, and what each fit measures: `share` (the
    depth a frame-to-frame fit confirms), `overlap` and `agreement` (of a fit from a prediction),
    each a number or a function of (source frame, target frame); `error` moves a fit from a
    prediction off the truth; `thumb` gives a frame's look (which keyframes look alike)."""

    def __init__(self, poses, bad=(), share=0.9, overlap=0.9, agreement=0.95, error=None, thumb=None):
        self.poses, self.bad = list(poses), set(bad)
        self.share, self.overlap, self.agreement = share, overlap, agreement
        self.error = np.eye(4) if error is None else error
        self.thumb = thumb or (lambda i: np.ones(4))
        self.fits_from = 0

    def value(self, v, s: int, t: int) -> float:
        return v(s, t) if callable(v) else v

    def truth(self, s: int, t: int) -> np.ndarray:
        return np.linalg.inv(self.poses[t]) @ self.poses[s]

    def load(self, i: int):
        if i in self.bad:
            raise FrameError(f"frame-{i}", "unreadable")
        return np.ones((120, 160), np.float32), np.zeros((120, 160), np.uint8)

    def run(self, monkeypatch, step=1) -> estimate.PoseEstimate:
        """Estimate the poses tracking every `step`-th frame (None: the default step)."""
        monkeypatch.setattr(estimate, "Odometry", lambda K, size: _Odometry(self))
        kwargs = {} if step is None else {"step": step}
        return estimate.estimate_poses(len(self.poses), self.load, (K, (160, 120)), **kwargs)


class _Odometry:
    def __init__(self, scene: Scene):
        self.scene = scene

    def view(self, index, depth, gray) -> View:
        return View(index, depth, gray, K, None, self.scene.thumb(index))

    def fit(self, source, target, min_inliers) -> Fit:
        share = self.scene.value(self.scene.share, source.index, target.index)
        return Fit(share >= min_inliers, self.scene.truth(source.index, target.index), share, 0.0, "scripted")

    def fit_from(self, source, target, predicted, min_overlap, min_agreement) -> Fit:
        self.scene.fits_from += 1
        s, t = source.index, target.index
        overlap = self.scene.value(self.scene.overlap, s, t)
        agreement = self.scene.value(self.scene.agreement, s, t)
        ok = overlap >= min_overlap and agreement >= min_agreement
        return Fit(ok, self.scene.truth(s, t) @ self.scene.error, overlap * agreement, 0.0, "scripted")


def walk(n: int, dx: float):
    return [pose(dx * i) for i in range(n)]


def test_every_4th_frame_is_tracked(monkeypatch):                       # DEFAULT_STEP
    est = Scene(walk(41, 0.01)).run(monkeypatch, step=None)
    assert est.processed == 11 and len(est.poses) == 41


def test_a_frame_is_tracked_when_half_its_depth_agrees(monkeypatch):    # TRACK_MIN_INLIERS
    assert len(Scene(walk(30, 0.01), share=0.55).run(monkeypatch).poses) == 30
    assert Scene(walk(30, 0.01), share=0.45).run(monkeypatch).poses == {}


def test_a_track_is_lost_after_6_unplaced_frames_in_a_row(monkeypatch):   # MAX_MISSES
    assert Scene(walk(40, 0.01), bad=range(20, 25)).run(monkeypatch).segments == 1
    assert Scene(walk(40, 0.01), bad=range(20, 26)).run(monkeypatch).segments == 2


def test_a_segment_of_10_frames_is_trusted(monkeypatch):                # MIN_SEGMENT_FRAMES
    assert 0 in Scene(walk(40, 0.01), bad=range(10, 16)).run(monkeypatch).poses      # frames 0-9
    short = Scene(walk(40, 0.01), bad=range(9, 15)).run(monkeypatch)                 # frames 0-8
    assert 0 not in short.poses and "only 9 frames" in short.unplaced[0]


def test_a_keyframe_every_15_cm(monkeypatch):                           # KEYFRAME_M
    assert Scene(walk(21, 0.16)).run(monkeypatch).keyframes == 21
    assert Scene(walk(21, 0.14)).run(monkeypatch).keyframes == 11


def test_a_keyframe_every_12_degrees(monkeypatch):                      # KEYFRAME_DEG
    assert Scene([pose(yaw_deg=13 * i) for i in range(21)]).run(monkeypatch).keyframes == 21
    assert Scene([pose(yaw_deg=11 * i) for i in range(21)]).run(monkeypatch).keyframes == 11


def there_and_back(offset: float, yaw_back: float = 0.0):
    """Out along x in 20 cm steps, back `offset` to the side (every frame a keyframe)."""
    out = [pose(0.2 * i) for i in range(11)]
    return out + [pose(2.0 - 0.2 * i, offset, yaw_back) for i in range(11)]


def test_a_loop_is_closed_within_60_cm(monkeypatch):                   # LOOP_RADIUS_M
    assert Scene(there_and_back(0.55)).run(monkeypatch).loop_closures > 0
    assert Scene(there_and_back(0.65)).run(monkeypatch).loop_closures == 0


def test_a_loop_is_closed_between_views_35_degrees_apart(monkeypatch):  # LOOP_AXIS_DEG
    assert Scene(there_and_back(0.3, yaw_back=30)).run(monkeypatch).loop_closures > 0
    assert Scene(there_and_back(0.3, yaw_back=40)).run(monkeypatch).loop_closures == 0


def out_and_back():
    """Six keyframes 16 cm apart, then back near the first three."""
    return [pose(0.16 * i) for i in range(6)] + [pose(0.1)]


def test_the_3_newest_keyframes_are_no_loop_and_2_older_ones_are_tried(monkeypatch):
    # LOOP_SKIP_KEYFRAMES, LOOP_CANDIDATES: straight on, the 4th newest keyframe is 64 cm back
    assert Scene(walk(12, 0.16)).run(monkeypatch).loop_closures == 0
    # back at 0.1 m: keyframes 0, 0.16 and 0.32 m lie near, the newest three do not count
    assert Scene(out_and_back()).run(monkeypatch).loop_closures == 2


def test_a_loop_closure_needs_half_the_depth_overlapping_and_85_percent_agreeing(monkeypatch):
    # LOOP_MIN_OVERLAP, LOOP_MIN_AGREEMENT
    assert Scene(out_and_back(), overlap=0.55).run(monkeypatch).loop_closures == 2
    assert Scene(out_and_back(), overlap=0.45).run(monkeypatch).loop_closures == 0
    assert Scene(out_and_back(), agreement=0.9).run(monkeypatch).loop_closures == 2
    assert Scene(out_and_back(), agreement=0.8).run(monkeypatch).loop_closures == 0


def _moved(metres: float = 0.0, degrees: float = 0.0) -> np.ndarray:
    return pose(metres, 0.0, degrees)


def test_a_loop_closure_moves_the_estimate_less_than_30_cm_and_15_degrees(monkeypatch):
    # LOOP_MAX_GAP_M, LOOP_MAX_GAP_DEG
    assert Scene(out_and_back(), error=_moved(metres=0.25)).run(monkeypatch).loop_closures == 2
    assert Scene(out_and_back(), error=_moved(metres=0.35)).run(monkeypatch).loop_closures == 0
    assert Scene(out_and_back(), error=_moved(degrees=14)).run(monkeypatch).loop_closures == 2
    assert Scene(out_and_back(), error=_moved(degrees=16)).run(monkeypatch).loop_closures == 0


def test_a_new_keyframe_is_fitted_to_the_2_before_it(monkeypatch):      # KEYFRAME_NEIGHBOURS
    scene = Scene(walk(12, 0.16))              # 12 keyframes, no loop: 0 + 1 + 2 x 10 fits
    scene.run(monkeypatch)
    assert scene.fits_from == 21


def two_segments(good_kf: int, good_share: float = 0.9) -> Scene:
    """Frames 0-19 (a keyframe each), 6 unreadable, then frames 26-39; the second segment cannot
    resume from the first (no overlap across), and fits to the first only to keyframe `good_kf`.
    The later a keyframe of the first segment, the more it looks like the second's."""
    first = set(range(20))

    def across(s, t):
        return (s in first) != (t in first)

    def share(s, t):
        return (good_share if good_kf in (s, t) else 0.1) if across(s, t) else 0.9
    return Scene([pose(0.2 * i) for i in range(20)] + [pose(0.01 * i) for i in range(20, 40)], bad=range(20, 26),
                 share=share, overlap=lambda s, t: 0.0 if across(s, t) else 0.9,
                 thumb=lambda i: np.array([float(i if i < 20 else 1), 0.0, 0.0, 0.0]))


def test_a_segment_is_linked_through_the_4_keyframes_that_look_most_alike(monkeypatch):   # LINK_CANDIDATES
    assert two_segments(good_kf=16).run(monkeypatch).linked_segments == 1     # 4th most alike
    assert two_segments(good_kf=15).run(monkeypatch).linked_segments == 0     # 5th


def test_a_segment_link_needs_60_percent_of_the_depth_agreeing(monkeypatch):   # LOOP_MIN_INLIERS
    assert two_segments(good_kf=19, good_share=0.65).run(monkeypatch).linked_segments == 1
    assert two_segments(good_kf=19, good_share=0.55).run(monkeypatch).linked_segments == 0
