"""Posed RGB-D sequences on disk -> lazily decoded `Frame`s.

Layouts (auto-detected by `open_sequence`):
- ``7scenes`` (also 3DMatch): ``frame-NNNNNN.color.jpg|png``, ``.depth.png`` (uint16 mm),
  ``.pose.txt`` (4x4 camera-to-world), ``camera-intrinsics.txt`` (3x3, here or one folder up).
- ``tum`` (TUM RGB-D): ``rgb.txt``, ``depth.txt``, ``groundtruth.txt`` (t tx ty tz qx qy qz qw),
  colour/depth/pose associated by nearest timestamp within ``max_dt`` seconds; depth scale 5000.
  Intrinsics from ``camera-intrinsics.txt`` / ``intrinsics.txt`` or, for the Freiburg
  recordings, the published calibration chosen by the folder name.
- ``scannet`` (SensReader export): ``color/N.jpg``, ``depth/N.png`` (mm), ``pose/N.txt``,
  ``intrinsic/intrinsic_color.txt`` (4x4) and ``intrinsic_depth.txt``.
- ``open3d`` (Open3D reconstruction system, Redwood): ``image/NNNNN.jpg|png``, ``depth/NNNNN.png``
  (mm, registered to colour), ``trajectory.log`` (a line ``i j n`` then the 4x4 camera-to-world
  pose of frame i, one block per frame) and an intrinsics JSON (Open3D
  ``PinholeCameraIntrinsic``: ``width``, ``height``, column-major ``intrinsic_matrix``).
- ``plain`` (your own recording): ``color/*.png|jpg`` and ``depth/*.png`` (uint16, registered to
  colour, paired by file name or else by order) and a one-line ``intrinsics.txt``
  (``fx fy cx cy`` [depth units per metre, 1000 = millimetres]); no poses.

A sequence without poses (the plain layout, 7-Scenes without ``.pose.txt`` files, Open3D without
``trajectory.log``, TUM without ``groundtruth.txt``) opens with `Sequence.has_poses()` false; `ingest.poses` estimates them and
`Sequence.use_poses` hands them to the frames.

Depth is delivered as float32 metres registered to the colour image (see `ingest.registration`),
raw 0 and 65535 read as 0 = invalid. A bad frame (missing or corrupt image, non-finite or
non-rigid pose, no timestamp match) is skipped and listed in `Sequence.skipped` as
(frame name, reason naming the file); a sequence without intrinsics is a `SequenceError`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Optional, Union

import cv2
import numpy as np

from core.errors import Sg3dError
from ingest.frames import Frame, FrameError, FrameSource
from ingest.image_checks import image_problem
from ingest.pose_check import pose_problem
from ingest.registration import DepthRegistrar, Registration

LAYOUTS = ("7scenes", "tum", "scannet", "open3d", "plain")
_ALIASES = {"3dmatch": "7scenes", "7-scenes": "7scenes", "tum-rgbd": "tum", "sens": "scannet",
            "redwood": "open3d", "folder": "plain"}

# Published calibration of the TUM RGB-D Freiburg cameras (fx, fy, cx, cy).
TUM_FREIBURG = {
    "freiburg1": (517.3, 516.5, 318.6, 255.3),
    "freiburg2": (520.9, 521.0, 325.1, 249.7),
    "freiburg3": (535.4, 539.2, 320.1, 247.6),
}


class SequenceError(Sg3dError, ValueError):
    """The sequence as a whole cannot be read (missing folder, unknown layout, no intrinsics);
    front ends show it as one line (ingest knows nothing of them)."""


@dataclass
class _Entry:
    name: str
    color: Path
    depth: Path
    timestamp: float
    pose: Optional[np.ndarray] = None      # already parsed (TUM)
    pose_file: Optional[Path] = None       # parsed when the frame is reached (7-Scenes, ScanNet)


# OpenCV reports undecodable files itself on stderr; a bad frame is named in Sequence.skipped
cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_ERROR)


class _FileSource:
    """Decodes one frame's files; every failure names the file."""

    __slots__ = ("entry", "seq", "registered")

    def __init__(self, entry: _Entry, seq: "Sequence", registered: bool = True):
        self.entry = entry
        self.seq = seq
        self.registered = registered  # False: depth in the depth camera's own pixels

    def _read(self, path: Path, flags: int) -> np.ndarray:
        if not path.is_file():
            raise FrameError(self.entry.name, f"missing {path.name}")
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise FrameError(self.entry.name, f"cannot read {path.name}: {exc.strerror or exc}") from None
        problem = image_problem(data, path.suffix)
        if problem:   # libjpeg/libpng would print their own complaint on stderr
            raise FrameError(self.entry.name, f"{path.name} {problem}")
        img = cv2.imdecode(np.frombuffer(data, np.uint8), flags)
        if img is None:
            raise FrameError(self.entry.name, f"cannot decode {path.name} (corrupt or not an image)")
        return img

    def _check_size(self, img: np.ndarray, path: Path, factor: int = 1) -> np.ndarray:
        w, h = self.seq.image_size
        if factor == 1 and (img.shape[1], img.shape[0]) != (w, h):
            raise FrameError(self.entry.name, f"{path.name} is {img.shape[1]}x{img.shape[0]}, "
                                              f"the sequence's colour images are {w}x{h}")
        return img

    def color(self) -> np.ndarray:
        img = self._read(self.entry.color, cv2.IMREAD_COLOR)
        return self._check_size(img, self.entry.color)

    def gray(self) -> np.ndarray:
        img = self._read(self.entry.color, cv2.IMREAD_GRAYSCALE)
        return self._check_size(img, self.entry.color)

    def preview(self, factor: int) -> np.ndarray:
        flags = {2: cv2.IMREAD_REDUCED_COLOR_2, 4: cv2.IMREAD_REDUCED_COLOR_4,
                 8: cv2.IMREAD_REDUCED_COLOR_8}.get(factor)
        if flags is None:
            img = self.color()
            return cv2.resize(img, (img.shape[1] // factor, img.shape[0] // factor), interpolation=cv2.INTER_AREA)
        return self._read(self.entry.color, flags)

    def depth(self) -> np.ndarray:
        raw = self._read(self.entry.depth, cv2.IMREAD_UNCHANGED)
        if raw.ndim != 2 or raw.dtype != np.uint16:
            raise FrameError(self.entry.name, f"{self.entry.depth.name} is not a 16-bit single-channel depth image")
        depth = raw.astype(np.float32)
        depth *= np.float32(1.0 / self.seq.depth_scale)
        depth[raw == 65535] = 0.0  # the sensor's "no reading" marker, like 0
        return self.seq.registrar(depth) if self.registered else depth


def _parse_pose(entry: _Entry) -> np.ndarray:
    if entry.pose is not None:
        pose = entry.pose
    else:
        path = entry.pose_file
        if path is None or not path.is_file():
            raise FrameError(entry.name, f"missing {path.name if path else 'pose'}")
        try:
            values = np.array(path.read_text().split(), dtype=np.float64)
        except ValueError:
            raise FrameError(entry.name, f"{path.name} is not a list of numbers") from None
        if values.size != 16:
            raise FrameError(entry.name, f"{path.name} holds {values.size} numbers, a 4x4 pose needs 16")
        pose = values.reshape(4, 4)
    source = entry.pose_file.name if entry.pose_file else "its pose"
    problem = pose_problem(pose, source)
    if problem:
        raise FrameError(entry.name, problem)
    return pose


class Sequence:
    """A posed RGB-D sequence: `len(seq)`, `seq.frames(...)`, `seq.K`, `seq.skipped`."""

    layout = ""
    depth_scale = 1000.0

    def __init__(self, path: Path, entries: list[_Entry], K: np.ndarray,
                 registration: Optional[Registration], skipped: list[tuple[str, str]]):
        self.path = path
        self.K = np.asarray(K, dtype=np.float64)
        self.registration = registration
        self._entries = entries
        self._skipped: dict[str, str] = dict(skipped)
        self.image_size = self._probe_size()
        self.registrar = DepthRegistrar(registration, self.K, self.image_size)

    def __len__(self) -> int:
        return len(self._entries)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({str(self.path)!r}, {len(self)} frames)"

    @property
    def skipped(self) -> list[tuple[str, str]]:
        """(frame name, reason) of every frame left out so far (listing and iteration)."""
        return list(self._skipped.items())

    def skip(self, name: str, reason: str) -> None:
        self._skipped.setdefault(name, reason)

    def has_poses(self) -> bool:
        """Whether the recording carries camera poses (some frame has a pose or a pose file)."""
        return any(e.pose is not None or (e.pose_file is not None and e.pose_file.is_file())
                   for e in self._entries)

    def name_of(self, i: int) -> str:
        return self._entries[i].name

    def timestamp_of(self, i: int) -> float:
        return self._entries[i].timestamp

    def pixels(self, i: int, registered: bool = True) -> FrameSource:
        """What decodes frame i's colour, depth and grey image (no pose needed); with
        `registered=False` the depth stays in the depth camera's pixels (see `depth_K`)."""
        source = self._source(self._entries[i])
        if not registered and isinstance(source, _FileSource):
            source.registered = False
        return source

    @property
    def depth_K(self) -> np.ndarray:
        """Intrinsics of the depth camera's own image: the given matrix unless the layout ships a
        separate one (7-Scenes' camera-intrinsics.txt is the depth camera's calibration)."""
        return getattr(self, "_depth_K", self.K)

    def use_poses(self, poses: dict[int, np.ndarray], unplaced: dict[int, str]) -> None:
        """Replace the frames' poses by estimated ones (frame index -> camera-to-world); a frame
        in `unplaced` is skipped with its reason when reached."""
        for i, entry in enumerate(self._entries):
            entry.pose = poses.get(i)
            entry.pose_file = None
        self._unplaced = {i: why for i, why in unplaced.items() if i not in poses}

    def _source(self, entry) -> "_FileSource":
        """What decodes one entry's pixels (a bag reader decodes messages instead of files)."""
        return _FileSource(entry, self)

    def _probe_size(self, probes: int = 5) -> tuple[int, int]:
        """The colour image size most of the first readable frames agree on (one odd image at the
        start must not make every other frame the wrong size)."""
        from collections import Counter

        sizes: Counter = Counter()
        for entry in self._entries[:50]:
            try:
                data = entry.color.read_bytes() if entry.color.is_file() else b""
            except OSError:
                data = b""
            ok = bool(data) and image_problem(data, entry.color.suffix) is None
            img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_GRAYSCALE) if ok else None
            if img is not None:
                sizes[(img.shape[1], img.shape[0])] += 1
                if sum(sizes.values()) >= probes:
                    break
        if not sizes:
            raise SequenceError(f"no readable colour image among the first frames of {self.path}")
        return sizes.most_common(1)[0][0]

    def frames(self, start: int = 0, stop: Optional[int] = None, step: int = 1,
               lazy: bool = False) -> Iterator[Frame]:
        """Yield frames in order. `lazy=False` decodes colour and depth before yielding (a bad
        image skips the frame); `lazy=True` yields frames that decode on first access, so a
        caller that only needs `frame.gray` or the pose never pays for the rest."""
        for i in range(start, len(self) if stop is None else min(stop, len(self)), step):
            try:
                yield self.frame(i, lazy=lazy)
            except FrameError:
                continue  # recorded in skipped

    def frame(self, i: int, lazy: bool = False) -> Frame:
        """One frame by position (raises FrameError when it is bad, after recording it in
        `skipped`)."""
        entry = self._entries[i]
        unplaced = getattr(self, "_unplaced", {})
        if i in unplaced:
            self.skip(entry.name, unplaced[i])
            raise FrameError(entry.name, unplaced[i])
        try:
            pose = _parse_pose(entry)
        except FrameError as exc:
            self.skip(exc.name, exc.reason)
            raise
        frame = Frame(i, None, None, self.K, pose, entry.timestamp, entry.name,
                      size=self.image_size, source=self._source(entry), on_error=self.skip)
        return frame if lazy else frame.load()


# -- intrinsics ------------------------------------------------------------------------------

def _read_matrix(path: Path) -> np.ndarray:
    try:
        values = np.array(path.read_text().split(), dtype=np.float64)
    except ValueError:
        raise SequenceError(f"{path} is not a list of numbers") from None
    if values.size == 9:
        K = values.reshape(3, 3)
    elif values.size == 16:
        K = values.reshape(4, 4)[:3, :3]
    elif values.size == 4:  # fx fy cx cy
        K = np.array([[values[0], 0, values[2]], [0, values[1], values[3]], [0, 0, 1]])
    else:
        raise SequenceError(f"{path} holds {values.size} numbers; expected a 3x3 or 4x4 matrix or fx fy cx cy")
    if not np.all(np.isfinite(K)) or K[0, 0] <= 0 or K[1, 1] <= 0:
        raise SequenceError(f"{path} does not hold valid intrinsics (focal lengths must be positive)")
    return K


# -- 7-Scenes / 3DMatch ----------------------------------------------------------------------

_SEVEN = re.compile(r"^(frame-(\d+))\.color\.(jpg|jpeg|png)$", re.IGNORECASE)


class SevenScenesSequence(Sequence):
    layout = "7scenes"
    depth_scale = 1000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "SevenScenesSequence":
        candidates = [path / "camera-intrinsics.txt", path.parent / "camera-intrinsics.txt"]
        intr = next((p for p in candidates if p.is_file()), None)
        if intr is None:
            raise SequenceError(f"missing intrinsics file {path / 'camera-intrinsics.txt'} "
                                f"(3x3 colour camera matrix; 7-Scenes' Kinect: fx=fy=585, cx=320, cy=240)")
        K = _read_matrix(intr)
        found = []
        for p in path.iterdir():
            m = _SEVEN.match(p.name)
            if m:
                found.append((int(m.group(2)), m.group(1), p))
        found.sort()
        entries, skipped = [], []
        for number, stem, color in found:
            depth = path / f"{stem}.depth.png"
            if not depth.is_file():
                skipped.append((stem, f"missing {depth.name}"))
                continue
            entries.append(_Entry(stem, color, depth, timestamp=number / 30.0,  # Kinect v1 runs at 30 Hz
                                  pose_file=path / f"{stem}.pose.txt"))
        if not entries:
            raise SequenceError(f"no frame-NNNNNN.color.jpg|png with a .depth.png in {path}")
        reg = Registration.seven_scenes() if registration is None else registration
        return cls(path, entries, K, reg, skipped)


# -- TUM RGB-D -------------------------------------------------------------------------------

def _read_list(path: Path, columns: int) -> list[list[str]]:
    rows = []
    for line in path.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split()
        if len(parts) >= columns:
            rows.append(parts)
    return rows


def _nearest(query: np.ndarray, reference: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index of the nearest reference timestamp for each query, and the absolute difference."""
    if reference.size == 0:
        return np.zeros(query.shape, int), np.full(query.shape, np.inf)
    order = np.argsort(reference)
    ref = reference[order]
    right = np.clip(np.searchsorted(ref, query), 0, ref.size - 1)
    left = np.clip(right - 1, 0, ref.size - 1)
    pick = np.where(np.abs(ref[left] - query) <= np.abs(ref[right] - query), left, right)
    return order[pick], np.abs(ref[pick] - query)


def quaternion_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (qx, qy, qz, qw), normalised first."""
    x, y, z, w = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


class TumSequence(Sequence):
    layout = "tum"
    depth_scale = 5000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None,
             max_dt: float = 0.02) -> "TumSequence":
        missing = [name for name in ("rgb.txt", "depth.txt") if not (path / name).is_file()]
        if missing:
            raise SequenceError(f"missing {', '.join(str(path / n) for n in missing)} (TUM RGB-D layout)")
        posed = (path / "groundtruth.txt").is_file()   # without it the poses are estimated
        K = cls._intrinsics(path)
        rgb = _read_list(path / "rgb.txt", 2)
        depth = _read_list(path / "depth.txt", 2)
        gt = _read_list(path / "groundtruth.txt", 8) if posed else []
        t_rgb = np.array([float(r[0]) for r in rgb])
        t_depth = np.array([float(r[0]) for r in depth])
        t_gt = np.array([float(r[0]) for r in gt])
        gt_values = np.array([[float(v) for v in r[1:8]] for r in gt]) if gt else np.zeros((0, 7))
        di, ddt = _nearest(t_rgb, t_depth)
        gi, gdt = _nearest(t_rgb, t_gt)
        entries, skipped = [], []
        for k, row in enumerate(rgb):
            name = Path(row[1]).stem
            if ddt[k] > max_dt:
                skipped.append((name, f"no depth image within {max_dt} s of {row[1]} in depth.txt"))
                continue
            if not posed:
                entries.append(_Entry(name, path / row[1], path / depth[di[k]][1], float(t_rgb[k])))
                continue
            if gdt[k] > max_dt:
                skipped.append((name, f"no pose within {max_dt} s of {row[1]} in groundtruth.txt"))
                continue
            values = gt_values[gi[k]]
            pose = np.eye(4)
            if np.all(np.isfinite(values)) and np.linalg.norm(values[3:7]) > 0:
                pose[:3, :3] = quaternion_to_matrix(values[3:7])
                pose[:3, 3] = values[:3]
            else:
                pose[:] = np.nan  # reported as a non-finite pose when the frame is reached
            entries.append(_Entry(name, path / row[1], path / depth[di[k]][1], float(t_rgb[k]), pose=pose))
        if not entries:
            raise SequenceError(f"no colour frame of {path / 'rgb.txt'} has depth and a pose within {max_dt} s")
        return cls(path, entries, K, registration, skipped)

    @staticmethod
    def _intrinsics(path: Path) -> np.ndarray:
        for name in ("camera-intrinsics.txt", "intrinsics.txt"):
            if (path / name).is_file():
                return _read_matrix(path / name)
        for key, (fx, fy, cx, cy) in TUM_FREIBURG.items():
            if key in path.resolve().name:
                return np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])
        raise SequenceError(f"missing intrinsics file {path / 'camera-intrinsics.txt'} (3x3 colour camera "
                            f"matrix, or fx fy cx cy); only rgbd_dataset_freiburg1/2/3_* folders have a default")


def _numbered_images(folder: Path) -> list[tuple[int, Path]]:
    """(number, path) of the images named by a frame number (``12.jpg``, ``00012.png``), in order."""
    return sorted((int(p.stem), p) for p in folder.iterdir()
                  if p.suffix.lower() in (".jpg", ".jpeg", ".png") and p.stem.isdigit())


# -- ScanNet ---------------------------------------------------------------------------------

class ScanNetSequence(Sequence):
    layout = "scannet"
    depth_scale = 1000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "ScanNetSequence":
        intr = path / "intrinsic" / "intrinsic_color.txt"
        if not intr.is_file():
            raise SequenceError(f"missing intrinsics file {intr} (ScanNet SensReader export)")
        K = _read_matrix(intr)
        if registration is None and (path / "intrinsic" / "intrinsic_depth.txt").is_file():
            registration = Registration.from_intrinsics(K, _read_matrix(path / "intrinsic" / "intrinsic_depth.txt"))
        if not (path / "color").is_dir():
            raise SequenceError(f"missing folder {path / 'color'} (ScanNet SensReader export)")
        entries, skipped = [], []
        for number, color in _numbered_images(path / "color"):
            depth = path / "depth" / f"{color.stem}.png"
            if not depth.is_file():
                skipped.append((color.stem, f"missing depth/{depth.name}"))
                continue
            entries.append(_Entry(color.stem, color, depth, timestamp=number / 30.0,
                                  pose_file=path / "pose" / f"{color.stem}.txt"))
        if not entries:
            raise SequenceError(f"no color/N.jpg with a depth/N.png in {path}")
        seq = cls(path, entries, K, registration, skipped)
        if (path / "intrinsic" / "intrinsic_depth.txt").is_file():
            seq._depth_K = _read_matrix(path / "intrinsic" / "intrinsic_depth.txt")
        return seq


# -- Open3D reconstruction system (Redwood) ---------------------------------------------------

def read_trajectory_log(path: Path) -> dict[int, np.ndarray]:
    """Redwood/Open3D ``trajectory.log``: blocks of a metadata line ``i j n`` and four rows of a
    4x4 camera-to-world matrix; frame i -> pose. A block that is not 16 numbers is a
    SequenceError naming its line (the file as a whole is unusable then)."""
    lines = [line.split() for line in path.read_text().splitlines() if line.strip()]
    if len(lines) % 5:
        raise SequenceError(f"{path} has {len(lines)} non-empty lines; a trajectory.log holds blocks of 5")
    poses = {}
    for b in range(0, len(lines), 5):
        try:
            index = int(lines[b][0])
            pose = np.array([[float(v) for v in row] for row in lines[b + 1:b + 5]], dtype=np.float64)
        except (ValueError, IndexError):
            raise SequenceError(f"{path} line {b + 1}: expected 'i j n' and four rows of 4 numbers") from None
        if pose.shape != (4, 4):
            raise SequenceError(f"{path} line {b + 2}: a pose needs four rows of 4 numbers")
        poses[index] = pose
    return poses


def _open3d_intrinsics(path: Path) -> np.ndarray:
    import json

    try:
        data = json.loads(path.read_text())
        values = np.asarray(data["intrinsic_matrix"], dtype=np.float64)
    except (ValueError, KeyError, TypeError):
        raise SequenceError(f"{path} is not an Open3D intrinsics JSON (needs 'intrinsic_matrix')") from None
    if values.size != 9:
        raise SequenceError(f"{path}: intrinsic_matrix holds {values.size} numbers, expected 9")
    K = values.reshape(3, 3).T  # Open3D writes the matrix column-major
    if not np.all(np.isfinite(K)) or K[0, 0] <= 0 or K[1, 1] <= 0:
        raise SequenceError(f"{path} does not hold valid intrinsics (focal lengths must be positive)")
    return K


class Open3dSequence(Sequence):
    layout = "open3d"
    depth_scale = 1000.0

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "Open3dSequence":
        intrinsics = sorted(p for p in path.glob("*.json") if "intrinsic_matrix" in p.read_text(errors="replace"))
        if not intrinsics:
            raise SequenceError(f"missing intrinsics JSON in {path} (Open3D PinholeCameraIntrinsic "
                                f"with 'intrinsic_matrix', e.g. camera_primesense.json)")
        K = _open3d_intrinsics(intrinsics[0])
        # without trajectory.log the poses are estimated (see ingest.poses)
        posed = (path / "trajectory.log").is_file()
        poses = read_trajectory_log(path / "trajectory.log") if posed else {}
        colour_dir = path / "image" if (path / "image").is_dir() else path / "color"
        entries, skipped = [], []
        for number, color in _numbered_images(colour_dir):
            depth = path / "depth" / f"{color.stem}.png"
            if not depth.is_file():
                skipped.append((color.stem, f"missing depth/{depth.name}"))
                continue
            if posed and number not in poses:
                skipped.append((color.stem, f"no pose for frame {number} in trajectory.log"))
                continue
            entries.append(_Entry(color.stem, color, depth, timestamp=number / 30.0, pose=poses.get(number)))
        if not entries:
            raise SequenceError(f"no {colour_dir.name}/NNNNN.jpg with a depth/NNNNN.png and a pose in {path}")
        return cls(path, entries, K, registration, skipped)


# -- a plain folder: your own recording ----------------------------------------------------------

PLAIN_INTRINSICS = ("intrinsics.txt", "camera-intrinsics.txt")
_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg")


class PlainSequence(Sequence):
    """``color/`` + ``depth/`` + a one-line ``intrinsics.txt``: what a RealSense or any RGB-D
    camera's recorder gives once the frames are saved as images. No poses."""

    layout = "plain"
    depth_scale = 1000.0

    @staticmethod
    def looks_like(path: Path) -> bool:
        """A color/ folder without ScanNet's intrinsic/ and pose/ (what else is missing is
        reported when it is opened)."""
        return (path / "color").is_dir() and not (path / "intrinsic").is_dir() and not (path / "pose").is_dir()

    @classmethod
    def open(cls, path: Path, registration: Optional[Registration] = None) -> "PlainSequence":
        intr = next((path / n for n in PLAIN_INTRINSICS if (path / n).is_file()), None)
        missing = []
        if not (path / "color").is_dir():
            missing.append("color/ (the colour images, .png or .jpg)")
        if not (path / "depth").is_dir():
            missing.append("depth/ (16-bit .png depth registered to colour, e.g. RealSense aligned depth)")
        if intr is None:
            missing.append("intrinsics.txt (one line: fx fy cx cy [depth units per metre]; from the "
                           "camera's calibration, e.g. `rs-enumerate-devices -c` for a RealSense)")
        if missing:
            raise SequenceError(f"{path} is missing " + "; ".join(missing))
        K, scale = _plain_intrinsics(intr)
        colours = sorted(p for p in (path / "color").iterdir() if p.suffix.lower() in _IMAGE_SUFFIXES)
        depths = sorted(p for p in (path / "depth").iterdir() if p.suffix.lower() == ".png")
        by_stem = {p.stem: p for p in depths}
        if colours and all(c.stem in by_stem for c in colours[:5]):
            pairs = [(c, by_stem.get(c.stem)) for c in colours]
        elif len(colours) == len(depths):
            pairs = list(zip(colours, depths))      # named differently: paired in order
        else:
            raise SequenceError(f"cannot pair {len(colours)} colour and {len(depths)} depth images in {path}: "
                                f"name them alike (color/000123.png with depth/000123.png) or give as many of each")
        entries, skipped = [], []
        for k, (color, depth) in enumerate(pairs):
            if depth is None:
                skipped.append((color.stem, f"missing depth/{color.stem}.png"))
                continue
            stamp = float(color.stem) if _is_number(color.stem) and len(color.stem) > 6 else k / 30.0
            entries.append(_Entry(color.stem, color, depth, timestamp=stamp))
        if not entries:
            raise SequenceError(f"no colour image in {path / 'color'} has a depth image")
        seq = cls(path, entries, K, registration, skipped)
        seq.depth_scale = scale
        return seq


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _plain_intrinsics(path: Path) -> tuple[np.ndarray, float]:
    """`fx fy cx cy [depth scale]` (or a 3x3 matrix) -> (K, depth units per metre)."""
    try:
        values = np.array(path.read_text().split(), dtype=np.float64)
    except ValueError:
        raise SequenceError(f"{path} is not a list of numbers (expected: fx fy cx cy [depth units per metre])") from None
    scale = 1000.0
    if values.size == 5:
        values, scale = values[:4], float(values[4])
        if not np.isfinite(scale) or scale <= 0:
            raise SequenceError(f"{path}: the depth scale (5th number) must be positive, e.g. 1000 for millimetres")
    if values.size not in (4, 9):
        raise SequenceError(f"{path} holds {values.size} numbers; expected fx fy cx cy [depth units per metre]")
    return _read_matrix_values(values, path), scale


def _read_matrix_values(values: np.ndarray, path: Path) -> np.ndarray:
    K = values.reshape(3, 3) if values.size == 9 else np.array(
        [[values[0], 0, values[2]], [0, values[1], values[3]], [0, 0, 1]])
    if not np.all(np.isfinite(K)) or K[0, 0] <= 0 or K[1, 1] <= 0:
        raise SequenceError(f"{path} does not hold valid intrinsics (focal lengths must be positive)")
    return K


# -- entry point -----------------------------------------------------------------------------

def detect_layout(path: Path) -> str:
    """The layout of a sequence folder, from the files it holds."""
    if (path / "rgb.txt").is_file() and (path / "depth.txt").is_file():
        return "tum"
    if (path / "trajectory.log").is_file() and (path / "depth").is_dir():
        return "open3d"
    if PlainSequence.looks_like(path):
        return "plain"
    if (path / "image").is_dir() and (path / "depth").is_dir() and any(path.glob("*.json")):
        return "open3d"
    if (path / "color").is_dir() and ((path / "intrinsic").is_dir() or (path / "depth").is_dir()):
        return "scannet"
    if (path / "camera-intrinsics.txt").is_file() or any(_SEVEN.match(p.name) for p in path.iterdir()):
        return "7scenes"
    raise SequenceError(f"cannot tell the layout of {path}: expected 7-Scenes (frame-NNNNNN.color.jpg), "
                        f"TUM RGB-D (rgb.txt, depth.txt), ScanNet (color/, depth/, pose/, intrinsic/) or "
                        f"Open3D (image/, depth/, trajectory.log, intrinsics JSON) or a plain folder "
                        f"(color/, depth/, intrinsics.txt)")


def open_sequence(path: Union[str, Path], layout: Optional[str] = None,
                  registration: Optional[Registration] = None, **bag_options) -> Sequence:
    """Open a posed RGB-D sequence folder, or a ROS bag (`ingest.bags`: a ROS1 .bag, a ROS2 bag
    folder, a bare .mcap or .db3). `layout`: one of LAYOUTS or "rosbag" (auto-detected when None);
    `registration`: depth-to-colour registration (None: the layout's default); `bag_options`:
    `ingest.bags.BagOptions` fields (topics, camera/world frame, max_dt), only for bags."""
    from ingest import bags

    path = Path(path).expanduser()
    if (layout or "").lower() in bags.LAYOUT_NAMES or (layout is None and (
            bags.is_bag(path) or (path.is_file() and bags.has_bag_magic(path)))):
        return bags.open_bag(path, registration=registration, **bag_options)
    if any(v is not None for v in bag_options.values()):
        raise SequenceError(f"{', '.join(k for k, v in bag_options.items() if v is not None)}: "
                            f"only for ROS bags, and {path} is not one")
    if path.is_file():
        raise SequenceError(f"{path} is a file, not a sequence folder or a ROS bag (.bag, .mcap, .db3, "
                            f"or a ROS2 bag folder)")
    if not path.is_dir():
        raise SequenceError(f"sequence folder not found: {path}")
    name = detect_layout(path) if layout is None else _ALIASES.get(layout.lower(), layout.lower())
    readers = {"7scenes": SevenScenesSequence, "tum": TumSequence, "scannet": ScanNetSequence,
               "open3d": Open3dSequence, "plain": PlainSequence}
    if name not in readers:
        raise SequenceError(f"unknown layout {layout!r}; choose one of {', '.join(LAYOUTS)}")
    return readers[name].open(path, registration=registration)
