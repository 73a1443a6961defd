"""An MCAP file that is still being recorded (`ros2 bag record -s mcap`) as a live source for
`sg3d map`: ROS 2 topics without a ROS install.

Why an MCAP file being recorded rather than Zenoh (rmw_zenoh's key expressions): it needs no
network setup, no matching of rmw_zenoh's key format and QoS (which changes between ROS 2
releases), and no second ROS-side bridge; it works with any ROS 2 distribution and middleware
(`ros2 bag record` is part of every install), the recording stays on disk for a later
`sg3d build`, and the same code reads a robot's finished recording. The cost is the recorder's
chunking: messages become visible when their chunk is written (rosbag2's default chunk is ~768
KB, a few camera frames), a fraction of a second at camera rates.

The file is read as it grows with the `mcap` package's stream reader, record by record: only
complete records are parsed (a record still being written is read again at the next `poll()`);
chunks are decompressed by `mcap` itself. Messages are decoded with rosbags' CDR support, and
paired with the helpers of `sg3d.ingest.readers.bag` (the reader of finished bags):

- colour: ``sensor_msgs/msg/Image`` (rgb8, bgr8, ...) or ``CompressedImage``; depth: ``Image``
  16UC1 (mm) / 32FC1 (m) or compressedDepth, registered to colour (realsense-ros'
  ``aligned_depth_to_color``; a depth topic of another size than colour is resampled, a depth
  image of another size than the topic's first is a bad frame, skipped); a topic's kind is read from its first
  message; the first colour and the first depth topic are followed, others are listed in
  `ignored`;
- intrinsics: ``sensor_msgs/msg/CameraInfo`` (the topic beside the colour topic, else the first);
- poses (camera-to-world of the colour images' optical frame): ``/tf`` + ``/tf_static`` (from
  the colour images' frame_id up to the root of its tree), else a ``nav_msgs/msg/Odometry``,
  ``PoseStamped`` or ``PoseWithCovarianceStamped`` topic; without either (decided once a second
  of colour images came without a pose channel), the frames carry a NaN pose and
  `sg3d.ingest.poses.online.OnlinePoses` tracks them.

Every colour image becomes a frame, in stamp order, once its depth and pose can be decided: a
depth image (and a pose sample) at or after its stamp arrived, or `GIVE_UP_S` of newer colour
images came without one. Depth is the nearest within `max_dt`, the pose is interpolated between
the samples around the stamp (`PoseSeries`, `TfTree`); a frame without either raises FrameError
with the reason when read (the mapper lists it and goes on). Memory: the last `ring` frames'
messages (raw bytes, decoded on demand), `DEPTHS_HELD` depth images, recent pose samples.
"""
from __future__ import annotations

import io
import struct
import threading
import time
from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any, Optional

import cv2
import numpy as np

from sg3d.ingest.readers.bag import (
    CAMERA_INFO,
    COMPRESSED,
    DEPTH_ENCODINGS,
    IMAGE,
    POSE_TYPES,
    TF,
    PoseSeries,
    TfTree,
    decode_colour,
    decode_depth,
    header_stamp,
)
from sg3d.ingest.readers.base import SequenceError
from sg3d.ingest.readers.frames import Frame, FrameError, FrameInfo
from sg3d.ingest.readers.kept import KeptFrames, ring_or_kept

MAGIC = b"\x89MCAP0\r\n"
OP_FOOTER = 0x02
RING_FRAMES = 90             # frames whose messages are held (3 s at 30 frames/s)
DEPTHS_HELD = 60             # depth images waiting for their colour image
GIVE_UP_S = 1.0              # colour images this much newer than a frame: its depth/pose is not coming
POSE_WAIT_S = 1.0            # colour images for this long without a pose channel: poses are estimated
MAX_READ = 64 << 20          # bytes read per poll (a long recording is caught up over several polls)
POSES_HELD = 4000            # pose samples kept per link (the oldest half is dropped past this)
TIMES_HELD = 100_000


@dataclass
class _Colour:
    stamp: int               # header stamp, ns
    raw: bytes
    msgtype: str
    frame_id: str
    arrived: float           # time.time() when read from the file


@dataclass
class _Held:
    """A frame: its messages (raw CDR) and what was paired with them, or why it cannot be used."""
    name: str
    stamp: int
    colour: Optional[tuple[bytes, str]] = None
    depth: Optional[tuple[bytes, str]] = None
    pose: Optional[np.ndarray] = None
    K: Optional[np.ndarray] = None
    size: Optional[tuple[int, int]] = None
    error: str = ""


class _Pixels:
    """Decodes one held frame's images on demand (a `FrameSource`)."""

    def __init__(self, held: _Held, follower: "McapFollower"):
        self.held, self.follower = held, follower

    def _msg(self, which: Optional[tuple[bytes, str]]) -> tuple[Any, str]:
        assert which is not None
        raw, msgtype = which
        try:
            return self.follower.typestore.deserialize_cdr(raw, msgtype), msgtype
        except Exception as exc:  # noqa: BLE001 - rosbags raises several kinds on damaged data
            raise FrameError(self.held.name, f"cannot decode {msgtype}: {exc}")

    def color(self) -> np.ndarray:
        msg, msgtype = self._msg(self.held.colour)
        return decode_colour(msg, msgtype, self.held.name)

    def gray(self) -> np.ndarray:
        msg, msgtype = self._msg(self.held.colour)
        return decode_colour(msg, msgtype, self.held.name, grey=True)

    def preview(self, factor: int) -> np.ndarray:
        img = self.color()
        return cv2.resize(img, (max(1, img.shape[1] // factor), max(1, img.shape[0] // factor)),
                          interpolation=cv2.INTER_AREA)

    def depth(self) -> np.ndarray:
        assert self.held.size is not None
        msg, msgtype = self._msg(self.held.depth)
        depth = decode_depth(msg, msgtype, self.held.name)
        size = (depth.shape[1], depth.shape[0])
        with self.follower._lock:
            first = self.follower.depth_size = self.follower.depth_size or size
        if size != first:       # a damaged or foreign image: resampling it would invent depths
            raise FrameError(self.held.name, f"depth image is {size[0]}x{size[1]}, the recording's depth "
                                             f"images are {first[0]}x{first[1]}")
        if size != self.held.size:    # a depth camera of another size than the colour camera's
            depth = cv2.resize(depth, self.held.size, interpolation=cv2.INTER_NEAREST)
        return depth


def _trim(series: PoseSeries) -> None:
    """Keep a pose series bounded: drop its oldest half past POSES_HELD samples."""
    if len(series) > POSES_HELD:
        keep = POSES_HELD // 2
        order = np.argsort(series._t, kind="stable")[-keep:]
        series._t = [series._t[k] for k in order]
        series._v = [series._v[k] for k in order]
        series._sorted = None


class McapFollower:
    """Follows an MCAP file while it is recorded; `poll()` reads what was appended (module doc)."""

    seq = None                     # nothing to read again: the final graph is the live evidence

    def __init__(self, path: Path, max_dt: float = 0.02, ring: int = RING_FRAMES):
        from rosbags.typesys import Stores, get_typestore

        self.path = Path(path).expanduser()
        self.tol = int(max_dt * 1e9)
        self.ring = int(ring)
        self.typestore: Any = get_typestore(Stores.LATEST)
        self.waiting_for = f"{self.path} to appear"
        self.ended = False                      # the footer was read: the recording is finished
        self.ignored: dict[str, str] = {}       # topic -> why it is not used
        self.depth_size: Optional[tuple[int, int]] = None   # the first depth image's: every other's
        self.pose_mode: Optional[str] = None    # "tf" | "topic" | "none" (estimated)
        self.sources: dict[str, str] = {}
        self._file: Optional[IO[bytes]] = None
        self._offset = 0
        self._buf = bytearray()
        self._schemas: dict[int, str] = {}
        self._channels: dict[int, tuple[str, str]] = {}       # id -> (topic, msgtype)
        self._roles: dict[int, str] = {}                      # id -> colour|depth|info|tf|tf_static|pose|ignored
        self._topic: dict[str, Optional[str]] = {"colour": None, "depth": None, "pose": None}
        self._infos: dict[str, tuple[np.ndarray, tuple[int, int]]] = {}
        self._pending: deque[_Colour] = deque()
        self._depths: deque[tuple[int, bytes, str]] = deque(maxlen=DEPTHS_HELD)
        self._newest = {"colour": -1, "depth": -1, "pose": -1}
        self._first_colour: Optional[int] = None
        self.tree = TfTree()
        self.series = PoseSeries()
        self._camera = self._world = ""
        self._frames: deque[_Held] = deque(maxlen=self.ring)
        self.kept = KeptFrames()                # frames mapping judged, past the ring
        self._times: deque[float] = deque(maxlen=max(TIMES_HELD, self.ring))
        self._count = 0
        self._lock = threading.Lock()

    # -- the LiveSource protocol ------------------------------------------------------------------
    def poll(self) -> int:
        with self._lock:
            self._read_appended()
            self._decide()
            return self._count

    def frame(self, i: int) -> Frame:
        name = f"frame-{i:06d}"
        with self._lock:
            held, kept = ring_or_kept(self._frames, self._count, i, name, self.ring, self.kept)
        if kept is not None:
            return kept
        if held.error:
            raise FrameError(held.name, held.error)
        assert held.K is not None and held.pose is not None
        return Frame(i, None, None, held.K, held.pose, FrameInfo(held.stamp / 1e9, held.name, held.size,
                                                                 _Pixels(held, self)))

    def keep(self, frame: Frame) -> None:
        """Keep a frame past the ring (`sg3d.ingest.readers.kept`): mapping judged it sharp, and
        the end of the map may detect it."""
        self.kept.keep(frame)

    @property
    def posed(self) -> Optional[bool]:
        """Whether its frames carry poses (/tf or a pose topic); None until the first frames tell."""
        return None if self.pose_mode is None else self.pose_mode != "none"

    def written_at(self, i: int) -> float:
        with self._lock:
            first = self._count - len(self._times)
            if first <= i < self._count:
                return float(self._times[i - first])
        return 0.0

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    # -- reading the growing file ------------------------------------------------------------------
    def _read_appended(self) -> None:
        if self.ended:
            return
        if self._file is None:
            if not self.path.is_file():
                return
            self._file = open(self.path, "rb")
            self.waiting_for = f"the first colour, depth and camera-info messages in {self.path}"
        self._file.seek(self._offset)
        data = self._file.read(MAX_READ)
        if not data:
            return
        self._offset += len(data)
        self._buf += data
        if self._offset == len(self._buf) and len(self._buf) >= len(MAGIC):     # the file's start
            if bytes(self._buf[:len(MAGIC)]) != MAGIC:
                raise SequenceError(f"{self.path} is not an MCAP file (it does not start with the MCAP magic)")
        start = len(MAGIC) if self._offset == len(self._buf) else 0
        if start and len(self._buf) < start:
            return
        end = pos = start
        footer = False
        while len(self._buf) - pos >= 9:
            opcode, length = struct.unpack_from("<BQ", self._buf, pos)
            if opcode == OP_FOOTER:
                footer = True
                break
            if len(self._buf) - pos - 9 < length:
                break
            pos += 9 + length
            end = pos
        if end > start:
            self._parse(bytes(self._buf[start:end]))
        del self._buf[:end]
        if footer:
            self.ended = True
            self._buf.clear()

    def _parse(self, records: bytes) -> None:
        from mcap.exceptions import EndOfFile
        from mcap.records import Channel, Message, Schema
        from mcap.stream_reader import StreamReader

        reader = StreamReader(io.BytesIO(records), skip_magic=True)
        try:
            for rec in reader.records:
                if isinstance(rec, Message):
                    self._message(rec.channel_id, rec.log_time, rec.data)
                elif isinstance(rec, Schema):
                    self._schemas[rec.id] = rec.name
                elif isinstance(rec, Channel):
                    msgtype = self._schemas.get(rec.schema_id, "")
                    self._channels[rec.id] = (rec.topic, msgtype)
                    if rec.message_encoding != "cdr":
                        self._roles[rec.id] = "ignored"
                        self.ignored[rec.topic] = f"message encoding {rec.message_encoding}, not cdr"
                    elif msgtype == CAMERA_INFO:
                        self._roles[rec.id] = "info"
                    elif msgtype == TF:
                        self._roles[rec.id] = "tf_static" if rec.topic.endswith("tf_static") else "tf"
                    elif msgtype in POSE_TYPES:
                        self._roles[rec.id] = "pose"
                    elif msgtype not in (IMAGE, COMPRESSED):
                        self._roles[rec.id] = "ignored"
        except EndOfFile:
            pass                   # the end of the complete records

    def _message(self, channel: int, log_time: int, raw: bytes) -> None:
        if channel not in self._channels:
            return
        topic, msgtype = self._channels[channel]
        role = self._roles.get(channel)
        if role == "ignored":
            return
        try:
            if role is None:                           # an image topic: colour or depth, from this message
                role = self._image_role(channel, topic, msgtype, raw)
                if role == "ignored":
                    return
            stamp = header_stamp(raw, ros1=False) or log_time
            if role == "colour":
                if self._first_colour is None:
                    self._first_colour = stamp
                frame_id = self._camera or self.typestore.deserialize_cdr(raw, msgtype).header.frame_id.lstrip("/")
                self._pending.append(_Colour(stamp, raw, msgtype, frame_id, time.time()))
                self._newest["colour"] = max(self._newest["colour"], stamp)
            elif role == "depth":
                self._depths.append((stamp, raw, msgtype))
                self._newest["depth"] = max(self._newest["depth"], stamp)
            elif role == "info" and topic not in self._infos:
                msg = self.typestore.deserialize_cdr(raw, msgtype)
                K = np.asarray(msg.k, dtype=np.float64).reshape(3, 3)
                if np.all(np.isfinite(K)) and K[0, 0] > 0 and K[1, 1] > 0:
                    self._infos[topic] = (K, (int(msg.width), int(msg.height)))
            elif role in ("tf", "tf_static"):
                msg = self.typestore.deserialize_cdr(raw, msgtype)
                self.tree.add(msg, static=role == "tf_static")
                if role == "tf":
                    for tf in msg.transforms:
                        self._newest["pose"] = max(self._newest["pose"], int(tf.header.stamp.sec) * 1_000_000_000
                                                   + int(tf.header.stamp.nanosec))
                    for series in self.tree.dynamic.values():
                        _trim(series)
            elif role == "pose":
                if self._topic["pose"] is None:
                    self._topic["pose"] = topic
                if topic != self._topic["pose"]:
                    self.ignored.setdefault(topic, f"a second pose topic (following {self._topic['pose']})")
                    return
                msg = self.typestore.deserialize_cdr(raw, msgtype)
                pose = msg.pose.pose if hasattr(msg.pose, "pose") else msg.pose
                self.series.add(stamp, pose.position, pose.orientation)
                self._newest["pose"] = max(self._newest["pose"], stamp)
                _trim(self.series)
        except Exception as exc:  # noqa: BLE001 - a damaged message is skipped, the recording goes on
            self.ignored.setdefault(f"{topic} (a message)", f"cannot be decoded: {exc}")

    def _image_role(self, channel: int, topic: str, msgtype: str, raw: bytes) -> str:
        msg = self.typestore.deserialize_cdr(raw, msgtype)
        if msgtype == COMPRESSED:
            kind = "depth" if "compresseddepth" in msg.format.lower() else "colour"
        else:
            kind = "depth" if msg.encoding.lower() in DEPTH_ENCODINGS else "colour"
        if self._topic[kind] is None:
            self._topic[kind] = topic
        role = kind if self._topic[kind] == topic else "ignored"
        if role == "ignored":
            self.ignored[topic] = f"a second {kind} topic (following {self._topic[kind]})"
        self._roles[channel] = role
        return role

    # -- pairing ---------------------------------------------------------------------------------
    def _info(self) -> Optional[tuple[np.ndarray, tuple[int, int]]]:
        colour = self._topic["colour"] or ""
        beside = [t for t in self._infos if t.rsplit("/", 1)[0] == colour.rsplit("/", 1)[0]]
        topic = beside[0] if beside else next(iter(self._infos), None)
        if topic is not None:
            self.sources["intrinsics"] = topic
        return self._infos[topic] if topic is not None else None

    def _decide(self) -> None:
        """Emit the waiting colour images, oldest first, whose depth and pose can be decided."""
        give_up_ns = int(GIVE_UP_S * 1e9)
        while self._pending:
            c = self._pending[0]
            late = self.ended or self._newest["colour"] - c.stamp > give_up_ns or len(self._pending) > self.ring
            if self.pose_mode is None:
                roles = set(self._roles.values())
                if "tf" in roles:
                    self.pose_mode = "tf"
                elif "pose" in roles:
                    self.pose_mode = "topic"
                elif late or self._newest["colour"] - (self._first_colour or 0) > POSE_WAIT_S * 1e9:
                    self.pose_mode = "none"
                else:
                    return
                self.sources["poses"] = {"tf": "/tf", "topic": "a pose topic",
                                         "none": "none (estimated from the images)"}[self.pose_mode]
            info = self._info()
            if not late and (info is None or self._newest["depth"] < c.stamp
                             or (self.pose_mode != "none" and self._newest["pose"] < c.stamp)):
                return
            self._pending.popleft()
            self._emit(c, info)

    def _emit(self, c: _Colour, info: Any) -> None:
        held = _Held(f"frame-{self._count:06d}", c.stamp, colour=(c.raw, c.msgtype))
        held.error = self._pair(c, held, info)
        self._frames.append(held)
        self._times.append(c.arrived)
        self._count += 1

    def _pair(self, c: _Colour, held: _Held, info: Any) -> str:
        """Fill `held` with depth, pose and intrinsics; the reason when one is missing."""
        t = c.stamp
        if info is None:
            return "no sensor_msgs/CameraInfo message yet: the intrinsics are unknown"
        held.K, held.size = info
        near = [d for d in self._depths if abs(d[0] - t) <= self.tol]
        if not near:
            return f"no depth on {self._topic['depth'] or 'a depth topic'} within {self.tol / 1e9:g} s of t={t / 1e9:.6f}"
        d = min(near, key=lambda d: abs(d[0] - t))
        held.depth = (d[1], d[2])
        if self.pose_mode == "none":
            held.pose = np.full((4, 4), np.nan)
            return ""
        if self.pose_mode == "tf":
            if not self._camera:
                self._camera = c.frame_id
                self._world = self.tree.chain(self._camera)[-1]
                self.sources["poses"] = f"/tf: {self._camera} in {self._world}"
            try:
                held.pose = self.tree.lookup(self._world, self._camera, t, self.tol)
            except LookupError as exc:
                return str(exc)
            return ""
        pose = self.series.at(t, self.tol)
        if pose is None:
            return f"no pose on {self._topic['pose']} within {self.tol / 1e9:g} s of t={t / 1e9:.6f}"
        held.pose = pose
        return ""
