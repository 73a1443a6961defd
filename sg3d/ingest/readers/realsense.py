"""A RealSense camera (or a RealSense recording played back) as a live source for `sg3d map`,
through Intel's `pyrealsense2` (`pip install 'sg3d[live]'`; wheels for Linux x86_64, and the
system's libusb: `apt-get install libusb-1.0-0`).

Source specs: ``realsense`` (the first device), ``realsense:SERIAL`` (that device),
``realsense:FILE`` (a recording: ``.bag`` from older librealsense, ``.db3`` from 2.57 on, played
back once at its recorded rate with ``enable_device_from_file(path, repeat_playback=False)``,
from the first `poll()` on: the first frame is what mapping sees first, as with a camera).

A camera streams depth (z16) and colour (bgr8) at 640x480, 30 frames/s; a recording plays the
streams it holds. Every frameset is aligned to colour (``rs.align(rs.stream.color)``: depth
registered to colour pixels, as every sg3d frame has it), depth is scaled to metres with the
device's depth scale, K is the colour stream's intrinsics. A RealSense has no poses: the frames
carry a NaN pose and `sg3d.ingest.poses.online.OnlinePoses` tracks them, on each frame's depth as
the depth camera measured it (`depth_camera`: its own pixels and intrinsics, the colour's grey
levels brought into them by the device's calibration), not on the depth aligned to colour.

Frames live in memory only: a ring keeps the last `ring` frames (90: three seconds), and
`frame(i)` of an older one raises FrameError("... no longer held ..."), unless mapping asked to
`keep` it (a sharp frame it judged, encoded within a memory budget: `sg3d.ingest.readers.kept`),
so memory stays bounded while a camera streams. A thread waits for the camera; `poll()` never blocks. Like a camera, a
recording plays at its recorded rate (`real_time`); framesets wait in a bounded queue while the
thread is busy, and those librealsense drops all the same are counted in `dropped` (gaps in the
frame numbers).
"""
from __future__ import annotations

import threading
import time
from collections import deque
from pathlib import Path
from typing import Any, Optional

import cv2
import numpy as np

from sg3d.ingest.readers.base import SequenceError
from sg3d.ingest.readers.depth_pixels import grey_in_depth_pixels
from sg3d.ingest.readers.frames import Frame, FrameError, FrameInfo, ring_item
from sg3d.ingest.readers.kept import KeptFrames, ring_or_kept

PREFIX = "realsense"
RING_FRAMES = 90              # frames held in memory (3 s at 30 frames/s)
TIMES_HELD = 100_000          # arrival times kept (for latency figures), about an hour at 30 frames/s
RECORDING_SUFFIXES = (".bag", ".db3")
CAMERA_STREAM = (640, 480, 30)
WAIT_MS = 1000

_COLOUR = {"bgr8": None, "rgb8": cv2.COLOR_RGB2BGR, "bgra8": cv2.COLOR_BGRA2BGR, "rgba8": cv2.COLOR_RGBA2BGR,
           "y8": cv2.COLOR_GRAY2BGR, "yuyv": cv2.COLOR_YUV2BGR_YUYV, "uyvy": cv2.COLOR_YUV2BGR_UYVY}


def is_realsense(spec: str) -> bool:
    """Whether a `sg3d map` SOURCE names a RealSense (``realsense`` or ``realsense:...``)."""
    return spec == PREFIX or spec.startswith(PREFIX + ":")


def import_realsense() -> Any:
    """The `pyrealsense2` module, or a SequenceError saying how to install it."""
    try:
        import pyrealsense2 as rs
    except ImportError as exc:
        why = str(exc)
        if "libusb" in why:
            raise SequenceError(f"pyrealsense2 cannot load: {why} (install the system's libusb: "
                                f"apt-get install libusb-1.0-0)")
        raise SequenceError(f"a RealSense source needs pyrealsense2: pip install 'sg3d[live]' ({why})")
    return rs


def depth_camera_of(profile: Any) -> tuple[Optional[np.ndarray], np.ndarray]:
    """The depth stream's K and its 4x4 motion into the colour camera (librealsense's calibration;
    a recording carries the device's), or (None, identity) when the streams do not say."""
    import pyrealsense2 as rs

    try:
        depth = profile.get_stream(rs.stream.depth).as_video_stream_profile()
        colour = profile.get_stream(rs.stream.color).as_video_stream_profile()
        i = depth.get_intrinsics()
        e = depth.get_extrinsics_to(colour)
    except RuntimeError:
        return None, np.eye(4)
    T = np.eye(4)
    T[:3, :3] = np.asarray(e.rotation, dtype=np.float64).reshape(3, 3).T    # librealsense: column-major
    T[:3, 3] = e.translation
    return np.array([[i.fx, 0, i.ppx], [0, i.fy, i.ppy], [0, 0, 1]], dtype=np.float64), T


def colour_to_bgr(img: np.ndarray, fmt: str) -> np.ndarray:
    """BGR uint8 from a RealSense colour frame's pixels in `fmt` (rs.format name)."""
    if fmt not in _COLOUR:
        raise ValueError(f"colour format {fmt} (use bgr8, rgb8, bgra8, rgba8, y8, yuyv or uyvy)")
    code = _COLOUR[fmt]
    return np.ascontiguousarray(img if code is None else cv2.cvtColor(img, code))


class RealSenseSource:
    """Frames of a RealSense camera or recording as they arrive (module docstring)."""

    seq = None                     # nothing to read again: the final graph is the live evidence
    has_poses = False

    def __init__(self, spec: str = PREFIX, ring: int = RING_FRAMES, real_time: bool = True):
        rs = import_realsense()
        self.rs = rs
        rest = spec[len(PREFIX) + 1:] if spec.startswith(PREFIX + ":") else ""
        self.file: Optional[Path] = None
        self.serial: Optional[str] = None
        if rest and (Path(rest).expanduser().suffix.lower() in RECORDING_SUFFIXES or Path(rest).expanduser().is_file()):
            self.file = Path(rest).expanduser()
            if not self.file.is_file():
                raise SequenceError(f"RealSense recording not found: {self.file}")
        elif rest:
            self.serial = rest
        self.ring = int(ring)
        self.what = f"RealSense recording {self.file}" if self.file else \
            f"RealSense {self.serial}" if self.serial else "the first RealSense camera"
        self.waiting_for = f"the first frames of {self.what}"
        self.ended = False
        self.error: Optional[str] = None
        self.K: Optional[np.ndarray] = None
        self.depth_scale = 0.0
        self._frames: deque = deque(maxlen=self.ring)      # (colour BGR, depth metres, timestamp s, raw depth)
        self.kept = KeptFrames()                           # frames mapping judged, past the ring
        self._times: deque = deque(maxlen=max(TIMES_HELD, self.ring))
        self._count = 0
        self.dropped = 0           # framesets the camera sent that were not taken (frame-number gaps)
        self._last_number: Optional[int] = None
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._pipeline = rs.pipeline()
        cfg = rs.config()
        if self.file is not None:
            cfg.enable_device_from_file(str(self.file), repeat_playback=False)
        else:
            if self.serial:
                cfg.enable_device(self.serial)
            w, h, fps = CAMERA_STREAM
            cfg.enable_stream(rs.stream.depth, w, h, rs.format.z16, fps)
            cfg.enable_stream(rs.stream.color, w, h, rs.format.bgr8, fps)
        # framesets wait in a queue of copies (`keep_frames`: out of librealsense's small frame pool)
        # while the thread aligns the one before: a busy moment drops none, up to `ring` of them
        self._queue = rs.frame_queue(self.ring, keep_frames=True)
        try:
            profile = self._pipeline.start(cfg, self._queue)
        except RuntimeError as exc:
            raise SequenceError(f"cannot start {self.what}: {exc}")
        device = profile.get_device()
        self._paused = False
        if self.file is not None:      # a recording plays from the first poll(), when mapping looks
            playback = device.as_playback()
            playback.set_real_time(real_time)
            playback.pause()
            self._paused = True
        try:
            self.depth_scale = float(device.first_depth_sensor().get_depth_scale())
        except RuntimeError as exc:
            self._pipeline.stop()
            raise SequenceError(f"{self.what} has no depth sensor: {exc}")
        colour = profile.get_stream(rs.stream.color).as_video_stream_profile().get_intrinsics()
        self.K = np.array([[colour.fx, 0, colour.ppx], [0, colour.fy, colour.ppy], [0, 0, 1]], dtype=np.float64)
        self.K_depth, self.depth_to_colour = depth_camera_of(profile)
        self._align = rs.align(rs.stream.color)
        self._thread = threading.Thread(target=self._run, name="sg3d-realsense", daemon=True)
        self._thread.start()

    # -- the camera thread -----------------------------------------------------------------------
    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                ok, frame = self._queue.try_wait_for_frame(WAIT_MS)
                if not ok:
                    if self.file is not None and self._stopped_playing():
                        break
                    continue
                if frame.is_frameset():
                    self._take(frame.as_frameset())
        except Exception as exc:   # noqa: BLE001 - a camera unplugged: poll() reports it
            self.error = f"{self.what} stopped: {exc}"
        finally:
            self.ended = True
            try:
                self._pipeline.stop()
            except RuntimeError:
                pass

    def _stopped_playing(self) -> bool:
        try:
            playback = self._pipeline.get_active_profile().get_device().as_playback()
            return playback.current_status() == self.rs.playback_status.stopped
        except RuntimeError:
            return True

    def _take(self, frames: Any) -> None:
        raw = frames.get_depth_frame()
        raw_mm = np.asanyarray(raw.get_data()).copy() if raw else None   # the frameset's memory goes back to librealsense
        aligned = self._align.process(frames)
        depth, colour = aligned.get_depth_frame(), aligned.get_color_frame()
        if not depth or not colour:
            return                 # a frameset with one stream only (start-up)
        fmt = str(colour.get_profile().format()).rsplit(".", 1)[-1]
        bgr = colour_to_bgr(np.asanyarray(colour.get_data()), fmt)
        metres = np.asanyarray(depth.get_data()).astype(np.float32) * np.float32(self.depth_scale)
        stamp = float(frames.get_timestamp()) / 1000.0
        number = int(colour.get_frame_number())
        if self._last_number is not None and number > self._last_number + 1:
            self.dropped += number - self._last_number - 1
        self._last_number = number
        with self._lock:
            self._frames.append((bgr, metres, stamp, raw_mm))
            self._times.append(time.time())
            self._count += 1

    # -- the LiveSource protocol ------------------------------------------------------------------
    def poll(self) -> int:
        if self._paused:
            self._paused = False
            self._pipeline.get_active_profile().get_device().as_playback().resume()
        if self.error is not None:
            raise SequenceError(self.error)
        return self._count

    def frame(self, i: int) -> Frame:
        name = f"realsense-{i:06d}"
        with self._lock:
            item, kept = ring_or_kept(self._frames, self._count, i, name, self.ring, self.kept)
        if kept is not None:
            return kept
        colour, depth, stamp, _ = item
        assert self.K is not None
        return Frame(i, colour, depth, self.K, np.full((4, 4), np.nan), FrameInfo(stamp, name))

    def depth_camera(self, i: int) -> Optional[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Frame i as odometry reads it: (depth in metres in the depth camera's own pixels, the
        colour's grey levels brought into them: `grey_in_depth_pixels`, the depth camera's K);
        None when the streams do not say how the depth camera sits (odometry then reads the
        aligned depth of every frame); FrameError when the ring no longer holds the frame (a frame
        kept past the ring keeps only its aligned depth)."""
        if self.K_depth is None:
            return None
        name = f"realsense-{i:06d}"
        with self._lock:
            colour, _, _, raw = ring_item(self._frames, self._count, i, name, self.ring)
        if raw is None:
            raise FrameError(name, "no depth of its own in the frameset")
        depth = raw.astype(np.float32) * np.float32(self.depth_scale)
        grey = cv2.cvtColor(colour, cv2.COLOR_BGR2GRAY)
        assert self.K is not None
        return depth, grey_in_depth_pixels(depth, self.K_depth, grey, self.K, self.depth_to_colour), self.K_depth

    def keep(self, frame: Frame) -> None:
        """Keep a frame past the ring (`sg3d.ingest.readers.kept`): mapping judged it sharp, and
        the end of the map may detect it."""
        self.kept.keep(frame)

    def written_at(self, i: int) -> float:
        with self._lock:
            first = self._count - len(self._times)
            if first <= i < self._count:
                return float(self._times[i - first])
        return 0.0                 # forgotten long ago

    def close(self) -> None:
        """Stop the camera (or the playback) and its thread."""
        self._stop.set()
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join(timeout=5)

    def __enter__(self) -> "RealSenseSource":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
