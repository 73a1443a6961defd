"""ROS bags as posed RGB-D sequences, read with PyPI `rosbags` (no ROS install).

Accepted: a ROS1 ``.bag``, a ROS2 bag folder (``metadata.yaml`` with sqlite3 or MCAP storage),
a bare ``.mcap`` or ``.db3`` file.

- colour: ``sensor_msgs/Image`` (rgb8, bgr8, rgba8, bgra8, mono8) or ``CompressedImage``
  (jpeg, png); depth: ``Image`` 16UC1/mono16 (millimetres) or 32FC1 (metres), or a
  ``compressedDepth`` ``CompressedImage``; depth is taken as registered to colour (ROS drivers'
  ``aligned_depth_to_color``), a different resolution is resampled;
- intrinsics: ``sensor_msgs/CameraInfo`` (its K; the topic beside the colour topic, else the
  only one);
- poses (camera-to-world of the optical frame: z forward, x right, y down): a
  ``geometry_msgs/PoseStamped``, ``PoseWithCovarianceStamped`` or ``nav_msgs/Odometry`` topic,
  or ``/tf`` + ``/tf_static`` from the camera frame (default: the colour images' frame_id) up to
  the world frame (default: the root of the camera frame's tree). Without either, the frames
  carry no pose and `sg3d.ingest.poses` estimates them.

A topic role with one candidate is picked; several candidates without a choice, or none, is a
`SequenceError` listing the topics and their types. Every colour message is a frame: depth and
pose are associated by header stamp within `max_dt` seconds (poses interpolated between
samples that bracket the stamp). A frame without depth or pose, with an unknown encoding or an
undecodable image is skipped with the reason (`Sequence.skipped`), never fatal.

Pixels are decoded lazily: opening reads every selected message once to index it (connection,
bag time, header stamp: bytes of the header only) and keeps no pixels; a frame's colour or depth
message is read again by its bag time when asked for. Memory is a few hundred bytes per
message, whatever the bag's size.
"""
from __future__ import annotations

import struct
import threading
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import cv2
import numpy as np

from sg3d.ingest.readers.base import Sequence, SequenceError, quaternion_to_matrix
from sg3d.ingest.readers.frames import FrameError
from sg3d.ingest.readers.registration import Registration

if TYPE_CHECKING:
    from rosbags.interfaces import Connection

LAYOUT_NAMES = ("rosbag", "ros", "bag", "mcap")
BAG_SUFFIXES = (".bag", ".mcap", ".db3")

IMAGE = "sensor_msgs/msg/Image"
COMPRESSED = "sensor_msgs/msg/CompressedImage"
CAMERA_INFO = "sensor_msgs/msg/CameraInfo"
POSE_TYPES = ("geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/PoseWithCovarianceStamped",
              "nav_msgs/msg/Odometry")
TF = "tf2_msgs/msg/TFMessage"

COLOUR_ENCODINGS = {"rgb8": cv2.COLOR_RGB2BGR, "bgr8": None, "rgba8": cv2.COLOR_RGBA2BGR,
                    "bgra8": cv2.COLOR_BGRA2BGR, "mono8": cv2.COLOR_GRAY2BGR, "8uc1": cv2.COLOR_GRAY2BGR,
                    "8uc3": None}
DEPTH_ENCODINGS = ("16uc1", "mono16", "32fc1")
MAX_INTERPOLATION_GAP = 0.5  # seconds: poses further apart are not interpolated between


@dataclass
class BagOptions:
    """Choices a user may give (`sg3d build --color-topic ...`); None = pick automatically."""
    color_topic: Optional[str] = None
    depth_topic: Optional[str] = None
    info_topic: Optional[str] = None
    pose_topic: Optional[str] = None     # a pose topic, or "tf" for /tf + /tf_static
    camera_frame: Optional[str] = None
    world_frame: Optional[str] = None
    max_dt: Optional[float] = None       # association tolerance in seconds [0.02]


BAG_MAGIC = (b"#ROSBAG V2.0", b"\x89MCAP", b"SQLite format 3\x00")


def has_bag_magic(path: Path) -> bool:
    """Whether a file starts like a ROS1 bag, an MCAP file or a ROS2 SQLite bag."""
    try:
        with open(path, "rb") as f:
            head = f.read(16)
    except OSError:
        return False
    return head.startswith(BAG_MAGIC)


def is_bag(path: Path) -> bool:
    """A ROS bag file (by its suffix) or a ROS2 bag folder (it holds metadata.yaml)."""
    path = Path(path)
    if path.suffix.lower() in BAG_SUFFIXES and not path.is_dir():
        return True
    return path.is_dir() and (path / "metadata.yaml").is_file()


# -- raw message helpers -----------------------------------------------------------------------

def header_stamp(raw: bytes, ros1: bool) -> int:
    """Nanoseconds of the std_msgs/Header stamp that starts `raw` (Image, CompressedImage,
    CameraInfo, PoseStamped, Odometry), read from the serialised bytes without decoding the rest.
    ROS1: uint32 seq, uint32 sec, uint32 nsec. CDR: 4-byte encapsulation header (byte 1 = 1:
    little endian), then int32 sec, uint32 nanosec."""
    if ros1:
        sec, nsec = struct.unpack_from("<II", raw, 4)
    else:
        sec, nsec = struct.unpack_from("<iI" if raw[1] == 1 else ">iI", raw, 4)
    return sec * 1_000_000_000 + nsec


def _stamp_ns(stamp: Any) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(getattr(stamp, "nanosec", 0))


def _rigid(translation: Any, rotation: Any) -> np.ndarray:
    T = np.eye(4)
    q = np.array([rotation.x, rotation.y, rotation.z, rotation.w], dtype=np.float64)
    if not np.all(np.isfinite(q)) or np.linalg.norm(q) == 0:
        T[:] = np.nan
        return T
    T[:3, :3] = quaternion_to_matrix(q)
    T[:3, 3] = (translation.x, translation.y, translation.z)
    return T


def _slerp(q0: np.ndarray, q1: np.ndarray, a: float) -> np.ndarray:
    q0 = q0 / np.linalg.norm(q0)
    q1 = q1 / np.linalg.norm(q1)
    d = float(np.dot(q0, q1))
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + a * (q1 - q0)
        return q / np.linalg.norm(q)
    theta = np.arccos(d)
    return (np.sin((1 - a) * theta) * q0 + np.sin(a * theta) * q1) / np.sin(theta)


class PoseSeries:
    """Timed rigid transforms of one link; `at(t)` interpolates between the samples around t
    (translation linearly, rotation by slerp) or takes the nearest within the tolerance."""

    def __init__(self) -> None:
        self._t: list[int] = []
        self._v: list[np.ndarray] = []   # tx ty tz qx qy qz qw
        self._sorted: Optional[tuple[np.ndarray, np.ndarray]] = None

    def add(self, t_ns: int, translation: Any, rotation: Any) -> None:
        self._t.append(t_ns)
        self._v.append(np.array([translation.x, translation.y, translation.z,
                                 rotation.x, rotation.y, rotation.z, rotation.w], dtype=np.float64))
        self._sorted = None

    def __len__(self) -> int:
        return len(self._t)

    def at(self, t_ns: int, tol_ns: int) -> Optional[np.ndarray]:
        if self._sorted is None:
            order = np.argsort(self._t, kind="stable")
            self._sorted = (np.asarray(self._t, dtype=np.int64)[order], np.asarray(self._v)[order])
        ts, vs = self._sorted
        if ts.size == 0:
            return None
        i = int(np.searchsorted(ts, t_ns))
        if i < ts.size and ts[i] == t_ns:
            v = vs[i]
        elif 0 < i < ts.size and ts[i] - ts[i - 1] <= MAX_INTERPOLATION_GAP * 1e9:
            a = (t_ns - ts[i - 1]) / (ts[i] - ts[i - 1])
            v = np.concatenate([vs[i - 1][:3] + a * (vs[i][:3] - vs[i - 1][:3]), _slerp(vs[i - 1][3:], vs[i][3:], a)])
        else:
            j = min((k for k in (i - 1, i) if 0 <= k < ts.size), key=lambda k: abs(int(ts[k]) - t_ns))
            if abs(int(ts[j]) - t_ns) > tol_ns:
                return None
            v = vs[j]
        T = np.eye(4)
        if not np.all(np.isfinite(v)) or np.linalg.norm(v[3:]) == 0:
            T[:] = np.nan
            return T
        T[:3, :3] = quaternion_to_matrix(v[3:])
        T[:3, 3] = v[:3]
        return T


class TfTree:
    """/tf and /tf_static: parent of each frame, a PoseSeries per dynamic link and one transform
    per static link; `lookup(world, camera, t)` chains them (camera-to-world)."""

    def __init__(self) -> None:
        self.parent: dict[str, str] = {}
        self.dynamic: dict[str, PoseSeries] = defaultdict(PoseSeries)
        self.static: dict[str, np.ndarray] = {}

    def add(self, msg: Any, static: bool) -> None:
        for tf in msg.transforms:
            child = tf.child_frame_id.lstrip("/")
            self.parent[child] = tf.header.frame_id.lstrip("/")
            if static:
                self.static[child] = _rigid(tf.transform.translation, tf.transform.rotation)
            else:
                self.dynamic[child].add(_stamp_ns(tf.header.stamp), tf.transform.translation, tf.transform.rotation)

    def chain(self, frame: str) -> list[str]:
        """`frame`, its parent, ... up to the root."""
        out = [frame]
        while out[-1] in self.parent and len(out) < 100 and self.parent[out[-1]] not in out:
            out.append(self.parent[out[-1]])
        return out

    def lookup(self, world: str, camera: str, t_ns: int, tol_ns: int) -> np.ndarray:
        """camera-to-world at t; raises LookupError naming the missing link."""
        chain = self.chain(camera)
        if world not in chain:
            raise LookupError(f"no transform chain from {camera} to {world} in /tf, /tf_static "
                              f"({camera}'s chain: {' -> '.join(chain)})")
        T = np.eye(4)
        for child in chain[:chain.index(world)]:
            link: Optional[np.ndarray]
            if child in self.static:
                link = self.static[child]
            else:
                link = self.dynamic[child].at(t_ns, tol_ns)
                if link is None:
                    raise LookupError(f"no /tf {self.parent[child]} -> {child} within {tol_ns / 1e9:g} s "
                                      f"of t={t_ns / 1e9:.6f}")
            T = link @ T
        return T


# -- image decoding -------------------------------------------------------------------------

def decode_colour(msg: Any, msgtype: str, where: str, grey: bool = False) -> np.ndarray:
    """BGR uint8 (or grey) from an Image or CompressedImage; FrameError names what is wrong."""
    if msgtype == COMPRESSED:
        fmt = msg.format.lower()
        if "compresseddepth" in fmt:
            raise FrameError(where, f"colour topic carries compressedDepth ({msg.format!r})")
        img = cv2.imdecode(np.asarray(msg.data, dtype=np.uint8), cv2.IMREAD_GRAYSCALE if grey else cv2.IMREAD_COLOR)
        if img is None:
            raise FrameError(where, f"cannot decode compressed image (format {msg.format!r})")
        return img
    enc = msg.encoding.lower()
    if enc not in COLOUR_ENCODINGS:
        raise FrameError(where, f"unknown colour encoding {msg.encoding!r} (use rgb8, bgr8, rgba8, bgra8, mono8)")
    channels = 1 if enc in ("mono8", "8uc1") else 4 if enc in ("rgba8", "bgra8") else 3
    data = np.asarray(msg.data, dtype=np.uint8)
    if msg.step < msg.width * channels or data.size < msg.step * msg.height:
        raise FrameError(where, f"{msg.encoding} image {msg.width}x{msg.height} has only {data.size} bytes")
    img = data[:msg.step * msg.height].reshape(msg.height, msg.step)[:, :msg.width * channels]
    img = img.reshape(msg.height, msg.width, channels) if channels > 1 else img
    code = COLOUR_ENCODINGS[enc]
    img = np.ascontiguousarray(img if code is None else cv2.cvtColor(img, code))
    if grey:
        return img if img.ndim == 2 else cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
    return cv2.cvtColor(img, cv2.COLOR_GRAY2BGR) if img.ndim == 2 else img


def decode_depth(msg: Any, msgtype: str, where: str) -> np.ndarray:
    """float32 metres (0 = invalid) from a depth Image (16UC1/mono16 mm, 32FC1 m) or a
    compressedDepth CompressedImage (12-byte header: int32 format, float32 depthQuantA, B; then
    a PNG of 16-bit mm, or of quantised inverse depth for 32FC1: d = A / (v - B))."""
    if msgtype == COMPRESSED:
        fmt = msg.format.lower()
        data = np.asarray(msg.data, dtype=np.uint8)
        if "compresseddepth" not in fmt or data.size <= 12:
            raise FrameError(where, f"depth topic carries a compressed image that is not compressedDepth ({msg.format!r})")
        _, qa, qb = struct.unpack_from("<iff", data.tobytes()[:12])
        raw = cv2.imdecode(data[12:], cv2.IMREAD_UNCHANGED)
        if raw is None or raw.dtype != np.uint16:
            raise FrameError(where, f"cannot decode compressedDepth image (format {msg.format!r})")
        if fmt.startswith("32fc1"):
            v = raw.astype(np.float32)
            depth = np.where(raw > 0, qa / np.maximum(v - qb, 1e-6), 0).astype(np.float32)
            return depth
        depth = raw.astype(np.float32) * np.float32(0.001)
        depth[raw == 65535] = 0
        return depth
    enc = msg.encoding.lower()
    if enc not in DEPTH_ENCODINGS:
        raise FrameError(where, f"unknown depth encoding {msg.encoding!r} (use 16UC1 mm or 32FC1 m)")
    itemsize = 4 if enc == "32fc1" else 2
    dtype = np.dtype(np.float32 if enc == "32fc1" else np.uint16).newbyteorder(">" if msg.is_bigendian else "<")
    data = np.asarray(msg.data, dtype=np.uint8)
    if msg.step < msg.width * itemsize or data.size < msg.step * msg.height:
        raise FrameError(where, f"{msg.encoding} depth {msg.width}x{msg.height} has only {data.size} bytes")
    rows = data[:msg.step * msg.height].reshape(msg.height, msg.step)[:, :msg.width * itemsize]
    raw = np.ascontiguousarray(rows).view(dtype).reshape(msg.height, msg.width)
    if enc == "32fc1":
        depth = raw.astype(np.float32)
        depth[~np.isfinite(depth) | (depth < 0)] = 0
        return depth
    depth = raw.astype(np.float32) * np.float32(0.001)
    depth[raw == 65535] = 0
    return depth


# -- the sequence ----------------------------------------------------------------------------

@dataclass
class _Ref:
    """Where one message lies: read again by (connection, bag time, n-th at that time)."""
    conn: Connection
    bag_ns: int
    nth: int
    stamp_ns: int


@dataclass
class _BagEntry:
    name: str
    color: _Ref
    depth: _Ref
    timestamp: float
    pose: Optional[np.ndarray]             # None: the bag carries no poses (estimated later)
    pose_file: None = None


class _BagSource:
    __slots__ = ("entry", "seq")

    def __init__(self, entry: _BagEntry, seq: "BagSequence"):
        self.entry = entry
        self.seq = seq

    def _colour(self, grey: bool) -> np.ndarray:
        msg, msgtype = self.seq.message(self.entry.color, self.entry.name)
        return decode_colour(msg, msgtype, self.entry.name, grey)

    def color(self) -> np.ndarray:
        return self._colour(False)

    def gray(self) -> np.ndarray:
        return self._colour(True)

    def preview(self, factor: int) -> np.ndarray:
        img = self.color()
        return cv2.resize(img, (max(1, img.shape[1] // factor), max(1, img.shape[0] // factor)),
                          interpolation=cv2.INTER_AREA)

    def depth(self) -> np.ndarray:
        msg, msgtype = self.seq.message(self.entry.depth, self.entry.name)
        return self.seq.registrar(decode_depth(msg, msgtype, self.entry.name))


@dataclass(frozen=True)
class _OpenBag:
    """An open bag: its reader, its images' size, and what `BagSequence.sources` says."""

    reader: Any
    image_size: tuple[int, int]
    sources: dict


class BagSequence(Sequence):
    """A ROS bag read as a posed RGB-D sequence; `sources` says which topics and frames it uses."""

    layout = "rosbag"

    def __init__(self, path: Path, bag: _OpenBag, entries: list, K: np.ndarray, registration: Any,
                 skipped: list[tuple[str, str]]) -> None:
        self._reader = bag.reader
        # rosbags' readers are not thread-safe, and frames are decoded ahead on a reader thread
        self._lock = threading.Lock()
        self._size = bag.image_size
        self.sources = bag.sources
        super().__init__(path, entries, K, registration, skipped)

    def _probe_size(self, probes: int = 5) -> tuple[int, int]:
        return self._size

    def _source(self, entry: Any) -> _BagSource:
        return _BagSource(entry, self)

    def message(self, ref: _Ref, name: str) -> tuple[Any, str]:
        """The message at `ref`, deserialised (raises FrameError when it cannot be read)."""
        try:
            with self._lock:
                k = 0
                for conn, _, raw in self._reader.messages([ref.conn], start=ref.bag_ns, stop=ref.bag_ns + 1):
                    if k == ref.nth:
                        return self._reader.deserialize(raw, conn.msgtype), conn.msgtype
                    k += 1
        except Exception as exc:  # a damaged bag: rosbags raises several kinds
            raise FrameError(name, f"cannot read {ref.conn.topic} at t={ref.bag_ns / 1e9:.6f}: {_why(exc)}") from None
        raise FrameError(name, f"message of {ref.conn.topic} at t={ref.bag_ns / 1e9:.6f} is gone")

    def close(self) -> None:
        self._reader.close()


def _why(exc: BaseException) -> str:
    """One line from an exception of rosbags (whose args are sometimes tuples)."""
    parts = []
    for a in exc.args:
        a = a[0] if isinstance(a, tuple) and len(a) == 1 else a
        parts.append(f"<{len(a)} bytes>" if isinstance(a, (bytes, bytearray)) else str(a))
    text = " ".join(" ".join(parts).split())
    if not text.isprintable() or "\\x" in text or len(text) > 200:   # raw bytes of a damaged file: never echoed
        return f"{type(exc).__name__} (the file is damaged or not a ROS bag)"
    return text or type(exc).__name__


def _topics_line(conns: Any) -> str:
    return ", ".join(f"{c.topic} ({c.msgtype.replace('/msg/', '/')})" for c in conns)


def _pick(role: str, flag: str, candidates: list, chosen: Optional[str], all_conns: list, path: Path) -> list:
    if chosen is not None:
        hits = [c for c in all_conns if c.topic == chosen]
        if not hits:
            raise SequenceError(f"{flag} {chosen}: no such topic in {path}; topics: {_topics_line(all_conns)}")
        return hits
    topics = sorted({c.topic for c in candidates})
    if len(topics) == 1:
        return [c for c in candidates if c.topic == topics[0]]
    if not topics:
        raise SequenceError(f"no {role} topic in {path}; topics: {_topics_line(all_conns) or 'none'}")
    raise SequenceError(f"{len(topics)} {role} topics in {path}: "
                        f"{_topics_line(sorted({c.topic: c for c in candidates}.values(), key=lambda c: c.topic))}; "
                        f"choose one with {flag}")


def _open_reader(path: Path) -> Any:
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    if not path.exists():
        raise SequenceError(f"ROS bag not found: {path}")
    try:
        reader = AnyReader([path], default_typestore=get_typestore(Stores.LATEST))
        reader.open()
    except Exception as exc:  # rosbags raises its own errors, struct/KeyError/OSError on damaged files
        raise SequenceError(f"cannot read ROS bag {path}: {_why(exc)}") from None
    return reader


def _refuse_missing(path: Path, conns: list, colour: list, depth: list, infos: list) -> None:
    """One error naming every piece the bag lacks and what would supply it."""
    missing = []
    if not colour:
        missing.append("a colour image topic (sensor_msgs/Image rgb8/bgr8 or CompressedImage; realsense-ros: "
                       "/camera/color/image_raw)")
    if not depth:
        missing.append("a depth image topic (Image 16UC1 mm or 32FC1 m, registered to colour; realsense-ros: "
                       "/camera/aligned_depth_to_color/image_raw, recorded with align_depth enabled)")
    if not infos:
        missing.append("a sensor_msgs/CameraInfo topic for the intrinsics (realsense-ros: /camera/color/camera_info)")
    if missing:
        raise SequenceError(f"{path} lacks " + "; ".join(missing) + f"; topics: {_topics_line(conns) or 'none'}")


def _first(reader: Any, conns: list) -> tuple[Any, Any]:
    for conn, _, raw in reader.messages(conns):
        return conn, reader.deserialize(raw, conn.msgtype)
    return None, None


def _image_kind(reader: Any, conn: Any) -> Optional[str]:
    """'colour' or 'depth' from the first message's encoding/format (None: no message)."""
    _, msg = _first(reader, [conn])
    if msg is None:
        return None
    if conn.msgtype == COMPRESSED:
        return "depth" if "compresseddepth" in msg.format.lower() else "colour"
    return "depth" if msg.encoding.lower() in DEPTH_ENCODINGS else "colour"


def open_bag(path: Any, registration: Optional[Registration] = None, **options: Any) -> BagSequence:
    """Open a ROS bag as a `BagSequence`; `options`: `BagOptions` fields."""
    opts = BagOptions(**options)
    path = Path(path).expanduser()
    reader = _open_reader(path)
    try:
        return _index(reader, path, opts, registration)
    except BaseException:
        reader.close()
        raise


@dataclass
class _PoseSource:
    """Where a bag's poses come from: /tf (`use_tf`), a pose topic, or nowhere (`none`: the
    poses are estimated from the images)."""
    use_tf: bool
    topic: Optional[list]          # the pose topic's connections
    tf_conns: list
    none: bool


def _index(reader: Any, path: Path, opts: BagOptions, registration: Optional[Registration]) -> BagSequence:
    """The bag's frames: the topics picked, one pass over their message headers, each colour
    image paired with the nearest depth image and its pose."""
    max_dt = 0.02 if opts.max_dt is None else float(opts.max_dt)
    conns = list(reader.connections)
    colour, depth, info = _image_topics(reader, conns, path, opts)
    K, info_msg = _intrinsics(reader, info, path)
    poses = _pose_source(conns, opts, path)
    refs, colour_frame, series, tree = _read_headers(reader, path, colour, depth, poses)
    camera = world = None
    if poses.use_tf:
        camera = (opts.camera_frame or colour_frame).lstrip("/")
        if not camera:
            raise SequenceError(f"the colour images of {colour[0].topic} name no frame_id; give --camera-frame "
                                f"(frames in /tf: {', '.join(sorted(tree.parent)) or 'none'})")
        world = (opts.world_frame or tree.chain(camera)[-1]).lstrip("/")
    entries, skipped = _pair_frames(refs, depth, poses, series, lambda t, tol: tree.lookup(world, camera, t, tol),
                                    max_dt)
    if not entries:
        reasons: defaultdict[str, int] = defaultdict(int)
        for _, why in skipped:
            reasons[why.split(" within ")[0].split(" of t=")[0]] += 1
        raise SequenceError(f"no colour frame of {path} has depth{'' if poses.none else ' and a pose'}: "
                            + "; ".join(f"{n}x {why}" for why, n in reasons.items()))
    size = _image_size(reader, info_msg, entries[0], colour, path)
    sources = {"color": _topics_line(colour[:1]), "depth": _topics_line(depth[:1]), "intrinsics": info[0].topic,
               "poses": ("none (estimated from the images)" if poses.none else
                         f"/tf: {camera} in {world}" if poses.use_tf else _topics_line((poses.topic or [])[:1])),
               "max_dt": max_dt, "colour_messages": len(refs["colour"]), "depth_messages": len(refs["depth"])}
    return BagSequence(path, _OpenBag(reader, size, sources), entries, K, registration, skipped)


def _image_topics(reader: Any, conns: list, path: Path, opts: BagOptions) -> tuple[list, list, list]:
    """The colour, depth and camera-info connections: the ones asked for, else the only topic of
    each kind (an image topic's kind is read from its first message); the camera info beside
    the colour topic first."""
    images = [c for c in conns if c.msgtype in (IMAGE, COMPRESSED)]
    kinds = {} if opts.color_topic and opts.depth_topic else {c.topic: _image_kind(reader, c) for c in images}
    colour_candidates = [c for c in images if kinds.get(c.topic) == "colour"]
    depth_candidates = [c for c in images if kinds.get(c.topic) == "depth"]
    infos = [c for c in conns if c.msgtype == CAMERA_INFO]
    _refuse_missing(path, conns, colour_candidates if opts.color_topic is None else [1],
                    depth_candidates if opts.depth_topic is None else [1], infos if opts.info_topic is None else [1])
    colour = _pick("colour image", "--color-topic", colour_candidates, opts.color_topic, conns, path)
    depth = _pick("depth image", "--depth-topic", depth_candidates, opts.depth_topic, conns, path)
    beside = [c for c in infos if c.topic.rsplit("/", 1)[0] == colour[0].topic.rsplit("/", 1)[0]]
    info = _pick("camera info", "--info-topic", beside or infos, opts.info_topic, conns, path)
    return colour, depth, info


def _intrinsics(reader: Any, info: list, path: Path) -> tuple[np.ndarray, Any]:
    """K from the first CameraInfo message (ROS2 `k`, ROS1 `K`), and the message."""
    _, info_msg = _first(reader, info)
    if info_msg is None:
        raise SequenceError(f"no message on {info[0].topic} in {path}: the intrinsics are unknown")
    K = np.asarray(getattr(info_msg, "k", None) if hasattr(info_msg, "k") else info_msg.K, dtype=np.float64).reshape(3, 3)
    if not np.all(np.isfinite(K)) or K[0, 0] <= 0 or K[1, 1] <= 0:
        raise SequenceError(f"{info[0].topic} in {path} holds no valid intrinsics (K = {K.ravel().tolist()})")
    return K, info_msg


def _pose_source(conns: list, opts: BagOptions, path: Path) -> _PoseSource:
    """A pose topic, or /tf when frames are named, no pose topic exists or "tf" is asked for."""
    pose_conns = [c for c in conns if c.msgtype in POSE_TYPES]
    tf_conns = [c for c in conns if c.msgtype == TF]
    use_tf = bool((opts.pose_topic or "").lower() == "tf" or (
        opts.pose_topic is None and (opts.camera_frame or opts.world_frame or not pose_conns) and tf_conns))
    pose_topic = None
    none = not use_tf and not pose_conns and opts.pose_topic is None   # poses are estimated then
    if not use_tf and not none:
        pose_topic = _pick("pose", "--pose-topic", pose_conns, opts.pose_topic, conns, path)
        if pose_topic[0].msgtype not in POSE_TYPES:
            raise SequenceError(f"--pose-topic {pose_topic[0].topic} is a {pose_topic[0].msgtype}, not one of "
                                f"{', '.join(POSE_TYPES)} (or give --pose-topic tf)")
    return _PoseSource(use_tf, pose_topic, tf_conns, none)


def _read_headers(reader: Any, path: Path, colour: list, depth: list, poses: _PoseSource) -> tuple[dict, str, Any, Any]:
    """One pass over the frames' messages (header stamps only, no pixels kept), then the poses:
    (refs by role, the colour images' frame_id, the pose series, the /tf tree)."""
    ros1 = not reader.is2
    refs: dict[str, list[_Ref]] = {"colour": [], "depth": []}
    role = {id(c): "colour" for c in colour} | {id(c): "depth" for c in depth}
    last: dict[tuple[int, int], int] = defaultdict(int)
    colour_frame = ""
    try:
        for conn, bag_ns, raw in reader.messages(colour + depth):
            key = (id(conn), bag_ns)
            nth = last[key]
            last[key] += 1
            stamp = header_stamp(raw, ros1) or bag_ns
            refs[role[id(conn)]].append(_Ref(conn, bag_ns, nth, stamp))
            if not colour_frame and role[id(conn)] == "colour":
                colour_frame = reader.deserialize(raw, conn.msgtype).header.frame_id.lstrip("/")
        series = PoseSeries()
        tree = TfTree()
        if poses.use_tf:
            for conn, _, raw in reader.messages(poses.tf_conns):
                tree.add(reader.deserialize(raw, conn.msgtype), static=conn.topic.endswith("tf_static"))
        elif poses.topic:      # (messages([]) would mean every topic)
            for conn, bag_ns, raw in reader.messages(poses.topic):
                msg = reader.deserialize(raw, conn.msgtype)
                pose = msg.pose.pose if hasattr(msg.pose, "pose") else msg.pose
                series.add(_stamp_ns(msg.header.stamp) or bag_ns, pose.position, pose.orientation)
    except (SequenceError, KeyboardInterrupt):
        raise
    except Exception as exc:  # truncated or damaged bag
        raise SequenceError(f"cannot read ROS bag {path}: {_why(exc)}") from None
    if not refs["colour"]:
        raise SequenceError(f"no message on the colour topic {colour[0].topic} in {path}")
    return refs, colour_frame, series, tree


def _pair_frames(refs: dict, depth: list, poses: _PoseSource, series: PoseSeries, tf_pose: Any,
                 max_dt: float) -> tuple[list, list]:
    """Each colour image with the depth image nearest in time (within max_dt) and its pose (from
    /tf through `tf_pose(t, tol)`, or the pose series); (entries, skipped with reasons)."""
    tol = int(max_dt * 1e9)
    depth_stamps = np.array([r.stamp_ns for r in refs["depth"]], dtype=np.int64)
    order = np.argsort(depth_stamps, kind="stable")
    depth_sorted = depth_stamps[order]
    entries, skipped = [], []
    for k, ref in enumerate(refs["colour"]):
        name = f"frame-{k:06d}"
        t = ref.stamp_ns
        i = int(np.searchsorted(depth_sorted, t))
        near = [j for j in (i - 1, i) if 0 <= j < depth_sorted.size]
        if not near or min(abs(int(depth_sorted[j]) - t) for j in near) > tol:
            skipped.append((name, f"no depth on {depth[0].topic} within {max_dt:g} s of t={t / 1e9:.6f}"))
            continue
        d_ref = refs["depth"][int(order[min(near, key=lambda j: abs(int(depth_sorted[j]) - t))])]
        if poses.none:
            pose = None
        elif poses.use_tf:
            try:
                pose = tf_pose(t, tol)
            except LookupError as exc:
                skipped.append((name, str(exc)))
                continue
        else:
            assert poses.topic is not None      # neither estimated nor /tf: a pose topic was picked
            pose = series.at(t, tol)
            if pose is None:
                skipped.append((name, f"no pose on {poses.topic[0].topic} within {max_dt:g} s of t={t / 1e9:.6f}"))
                continue
        entries.append(_BagEntry(name, ref, d_ref, t / 1e9, pose))
    return entries, skipped


def _image_size(reader: Any, info_msg: Any, first: _BagEntry, colour: list, path: Path) -> tuple[int, int]:
    """(width, height) from CameraInfo, else from the first colour image."""
    width, height = int(info_msg.width), int(info_msg.height)
    if width <= 0 or height <= 0:
        msg = reader.deserialize(_raw_of(reader, first.color), colour[0].msgtype)
        try:
            img = decode_colour(msg, colour[0].msgtype, first.name, grey=True)
        except FrameError as exc:
            raise SequenceError(f"{path}: CameraInfo has no image size and {exc}") from None
        width, height = img.shape[1], img.shape[0]
    return width, height


def _raw_of(reader: Any, ref: _Ref) -> bytes:
    for k, (_, _, raw) in enumerate(reader.messages([ref.conn], start=ref.bag_ns, stop=ref.bag_ns + 1)):
        if k == ref.nth:
            return raw
    raise SequenceError(f"message of {ref.conn.topic} at t={ref.bag_ns / 1e9:.6f} is gone")
