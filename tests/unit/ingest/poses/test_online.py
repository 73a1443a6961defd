"""Online tracking's rules for a camera without poses (`sg3d.ingest.poses.online`) and the live
loop's budget for it (`sg3d.ingest.live`): the constant-velocity prediction, and when mapping
jumps to the newest frame or lets detection wait (the real odometry on real frames:
tests/e2e/test_map_no_poses.py)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from scipy.spatial.transform import Rotation

from sg3d.ingest import live
from sg3d.ingest.poses import online
from sg3d.ingest.poses.tracking import motion_gap


def pose(x: float = 0.0, yaw_deg: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("y", yaw_deg, degrees=True).as_matrix()
    T[:3, 3] = (x, 0.0, 0.0)
    return T


def walk(n: int, dx: float, dyaw: float, dt: float = 1 / 30) -> list[tuple[float, np.ndarray]]:
    """A camera turning and moving along its own x axis at a constant rate."""
    out, T = [], np.eye(4)
    for i in range(n):
        out.append((i * dt, T))
        T = T @ pose(dx, dyaw)
    return out


def test_the_prediction_carries_a_constant_motion_on():
    history = walk(10, 0.01, 1.0)
    t_last, last = history[-1]
    truth = last
    for _ in range(20):                   # 20 frames later, the same motion per frame
        truth = truth @ pose(0.01, 1.0)
    predicted = online.predict_pose(history, t_last + 20 / 30)
    metres, degrees = motion_gap(truth, predicted)
    assert metres < 0.01 and degrees < 0.1, (metres, degrees)


def test_no_prediction_from_one_pose_or_too_far_ahead():              # MAX_PREDICT_S
    history = walk(10, 0.01, 1.0)
    t_last = history[-1][0]
    assert online.predict_pose(history[:1], t_last + 0.1) is None
    assert online.predict_pose(history, t_last + online.MAX_PREDICT_S - 0.01) is not None
    assert online.predict_pose(history, t_last + online.MAX_PREDICT_S + 0.01) is None


def test_the_velocity_is_the_motion_of_the_last_0_3_s():              # VELOCITY_WINDOW_S
    # a camera at rest until 1 s, then moving 1 cm a frame: a window reaching back before the
    # start of the motion would halve the speed
    history = [(i / 30, np.eye(4)) for i in range(30)]
    T = np.eye(4)
    for i in range(30, 45):
        T = T @ pose(0.01)
        history.append((i / 30, T))
    t_last, last = history[-1]
    predicted = online.predict_pose(history, t_last + 10 / 30)
    assert abs((np.linalg.inv(last) @ predicted)[0, 3] - 0.10) < 0.005
    assert online.VELOCITY_WINDOW_S == 0.3


def _mapper(tracked: bool, backlog: int, since_detect: float):
    m = SimpleNamespace(live=True, counts=live.LiveCounts(), _last_detect=live.time.monotonic() - since_detect)
    m.tracked = lambda: tracked
    m.backlog = lambda: backlog
    m.max_backlog = lambda: live.LiveMapper.max_backlog(m)
    return m


def test_a_tracked_source_jumps_when_more_than_2_frames_wait():        # TRACKED_BACKLOG
    assert live.TRACKED_BACKLOG == 2
    assert live.LiveMapper.max_backlog(_mapper(True, 0, 0)) == 2
    assert live.LiveMapper.max_backlog(_mapper(False, 0, 0)) == live.MAX_BACKLOG


def test_detection_waits_for_tracking_but_at_most_half_a_second():     # DETECT_EVERY_S
    assert live.LiveMapper.may_detect(_mapper(True, 2, 0.0))           # tracking caught up
    waiting = _mapper(True, 3, 0.4)
    assert not live.LiveMapper.may_detect(waiting) and waiting.counts.detect_deferred == 1
    assert live.LiveMapper.may_detect(_mapper(True, 3, 0.6))           # half a second without one
    assert live.LiveMapper.may_detect(_mapper(False, 30, 0.0))         # poses given: no tracking to wait for


class _Odometry:
    """Stands in for `tracking.Odometry`: a frame fits unless it is in `bad`; no guessed fit works."""

    bad: set = set()

    def __init__(self, *args, **kwargs):
        pass

    def view(self, index, depth, gray):
        return SimpleNamespace(index=index, depth=depth, gray=gray)

    def fit(self, view, target, min_inliers):
        from sg3d.ingest.poses.tracking import Fit

        return Fit(view.index not in self.bad, np.eye(4), 0.9, 0.01, "no fit")

    fit_depth = fit

    def images_agree(self, source, target, motion):
        return None                        # hand-made views: no images to judge by

    def fit_from(self, view, target, guess, min_overlap, min_agreement):
        from sg3d.ingest.poses.tracking import Fit

        return Fit(False, guess, 0.0, float("inf"), "no fit")


class _Frames:
    """A pose-less source: frame i at time i / fps."""

    seq = None

    def __init__(self, fps: float):
        self.fps = fps

    def poll(self) -> int:
        return 1000

    def written_at(self, i: int) -> float:
        return i / self.fps

    def frame(self, i: int):
        from sg3d.ingest.readers.frames import Frame, FrameInfo

        K = np.array([[100.0, 0, 20], [0, 100.0, 15], [0, 0, 1]])
        return Frame(i, np.zeros((30, 40, 3), np.uint8), np.ones((30, 40), np.float32), K, np.full((4, 4), np.nan),
                     FrameInfo(i / self.fps, f"frame-{i}"))


def _restarts(monkeypatch, fps: float, bad: range) -> int:
    monkeypatch.setattr(online, "Odometry", _Odometry)
    monkeypatch.setattr(_Odometry, "bad", set(bad))
    tracker = online.OnlinePoses(_Frames(fps))
    for i in range(bad.stop + 2):
        try:
            tracker.frame(i)
        except Exception:      # noqa: BLE001 - the lost frames
            pass
    return tracker.restarts


def test_a_track_restarts_after_2_lost_frames_and_0_7_s(monkeypatch):    # MAX_LOST, MAX_LOST_S
    assert online.MAX_LOST == 2 and online.MAX_LOST_S == 0.7
    # frames 0-4 placed (the last at 4 s or 0.4 s); a restart is the frame that fails after that
    assert _restarts(monkeypatch, 1.0, range(5, 8)) == 1      # frame 7: 2 lost before it, 3 s without a pose
    assert _restarts(monkeypatch, 1.0, range(5, 7)) == 0      # frame 7 fits again
    assert _restarts(monkeypatch, 10.0, range(5, 12)) == 1    # frame 11: 0.7 s without a pose
    assert _restarts(monkeypatch, 10.0, range(5, 11)) == 0    # frame 10 at 0.6 s still relocalises; 11 fits


def test_a_lost_frame_relocalises_for_0_3_s_after_the_bridges(monkeypatch):   # LOSS_BUDGET_S
    assert online.LOSS_BUDGET_S == 0.3
    calls = []

    class _Slow(_Odometry):
        def fit_from(self, view, target, guess, min_overlap, min_agreement):
            calls.append((view.index, target.index))
            online.time.sleep(0.11)
            return super().fit_from(view, target, guess, min_overlap, min_agreement)

    monkeypatch.setattr(online, "Odometry", _Slow)
    monkeypatch.setattr(online, "KEYFRAME_M", 0.0)          # every placed frame a keyframe: 0-4 held
    monkeypatch.setattr(_Odometry, "bad", {5})
    tracker = online.OnlinePoses(_Frames(10.0))
    for i in range(6):
        try:
            tracker.frame(i)
        except Exception:      # noqa: BLE001 - the lost frame
            pass
    # frame 5: the 3 rounds from the prediction to keyframe 4 (the last frame too) always run (0.33 s);
    # relocalisation on the 2 older keyframes (2 rounds each) starts no round past 0.3 s: 3 fits, not 4
    assert [t for i, t in calls if i == 5] == [4, 4, 4, 3, 3, 2], calls


def test_the_frames_tracking_went_past_take_poses_between_the_placed_ones():     # filled_poses
    path = walk(11, 0.01, 1.0)
    times = [t for t, _ in path]
    placed = {0: path[0][1], 5: path[5][1], 10: path[10][1]}
    filled = online.filled_poses(placed, times, unplaced={7})
    assert sorted(filled) == [0, 1, 2, 3, 4, 5, 6, 8, 9, 10]          # 7: lost, stays unplaced
    for i in (0, 5, 10):
        assert np.array_equal(filled[i], placed[i])
    for i in (2, 8):                      # on a constant motion, within a millimetre and 0.1 degree
        metres, degrees = motion_gap(path[i][1], filled[i])
        assert metres < 1e-3 and degrees < 0.1, (i, metres, degrees)


def test_no_pose_outside_the_placed_frames():
    path = walk(10, 0.01, 1.0)
    times = [t for t, _ in path]
    assert sorted(online.filled_poses({3: path[3][1], 6: path[6][1]}, times, set())) == [3, 4, 5, 6]
    assert online.filled_poses({}, times, set()) == {}


def test_frames_that_arrived_count_as_received_while_tracking_deals_with_one():
    # tracking one frame took 2-4 s on busy cores: counting only the frames it had dealt with, a
    # map stopped as idle (--stop-when-idle 3) after 199 of the kitchen's 1000 frames
    from sg3d.ingest.pipeline import Settings

    source = SimpleNamespace(posed=False, poll=lambda: 12, arrived=40, revision=0)
    mapper = live.LiveMapper(source, None, Settings(), "r", "b")
    mapper.next_frame = 12
    mapper.look()
    assert mapper.counts.received == 40


def test_frames_there_at_the_start_are_tracked_in_order_then_the_newest():   # next_to_track
    assert online.next_to_track(0, 1000, 1000, 6, 45) == 0          # a folder written before: in order
    assert online.next_to_track(999, 1000, 1000, 6, 45) == 999
    assert online.next_to_track(1000, 1003, 1000, 6, 45) == 1002    # past them: the camera's newest frame
    assert online.next_to_track(3, 6, 3, 6, 45) == 5                # a camera: a few frames held at the start
    assert online.next_to_track(0, 40, 0, 6, 45) == 39              # the first frame: the newest


def test_behind_the_camera_tracking_steps_at_most_a_stride_then_jumps_past_the_lag():   # next_to_track
    assert online.next_to_track(101, 106, 0, 6, 45) == 105          # within a stride: the newest
    assert online.next_to_track(101, 107, 0, 6, 45) == 106          # a stride ahead: the newest still
    assert online.next_to_track(101, 108, 0, 6, 45) == 106          # past a stride: one stride on
    assert online.next_to_track(101, 152, 0, 6, 45) == 106          # 45 frames behind the step: still steps
    assert online.next_to_track(101, 153, 0, 6, 45) == 152          # 46 behind: jumps to the newest
    assert online.next_to_track(101, 120, 0, 0, 45) == 101          # a stride of 0 still moves on


def test_track_steps_follow_the_frame_rate_and_the_cameras_ring():
    assert online.track_steps(1 / 30, None) == (6, 45)              # 0.2 s and 1.5 s at 30 frames/s
    assert online.track_steps(1 / 15, None) == (3, 22)
    assert online.track_steps(1 / 30, 90) == (6, 45)                # half of a 90-frame ring: the same
    assert online.track_steps(1 / 30, 60) == (6, 30)                # a smaller ring bounds the lag
    assert online.track_steps(1.0, None) == (1, 2)                  # one frame a second: every frame


def test_a_fit_counts_when_its_images_agree_at_least_0_93(monkeypatch):   # TRACK_IMAGE_NCC
    from sg3d.ingest.poses.tracking import Fit, Odometry, image_agreement

    K = np.array([[100.0, 0, 79.5], [0, 100.0, 59.5], [0, 0, 1]])
    odometry = Odometry(K, (160, 120))
    stripes = (np.arange(160)[None, :].repeat(120, 0) // 8 % 2 * 120 + 60).astype(np.float32)
    noise = np.random.default_rng(1).normal(0, 1, (120, 160))
    wall = np.full((120, 160), 1.5, np.float32)

    def seen_with(sigma):
        return odometry.view(1, wall, np.clip(stripes + sigma * noise, 0, 255).astype(np.uint8))

    tracker = online.OnlinePoses(_Frames(30.0))
    tracker._odometry = odometry
    source, fit = odometry.view(0, wall, stripes.astype(np.uint8)), Fit(True, np.eye(4), 0.9, 0.01)
    below, above = seen_with(30.0), seen_with(18.0)
    assert image_agreement(source, below, K, np.eye(4)) < online.TRACK_IMAGE_NCC < image_agreement(source, above, K, np.eye(4))
    assert not tracker._confirmed(fit, source, below)
    assert tracker._confirmed(fit, source, above)
    assert not tracker._confirmed(Fit(False, np.eye(4), 0.9, 0.01), source, above)   # the depth said no
