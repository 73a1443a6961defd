"""What every layout shares: `Sequence` (lazily decoded, checked frames), its errors, and the
intrinsics and pose readers (`sg3d.ingest.readers` opens a folder or a bag)."""
from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Optional

import cv2
import numpy as np

from sg3d.core.errors import Sg3dError
from sg3d.ingest.readers.frames import Frame, FrameError, FrameInfo, FrameSource
from sg3d.ingest.readers.image_checks import PNG_SIGNATURE, image_problem
from sg3d.ingest.readers.pose_check import implausible_motion, pose_problem, rigid
from sg3d.ingest.readers.registration import DepthRegistrar, Registration


# The recording's colour and depth image sizes are the ones most of its first this many readable
# images agree on (`Sequence._probe_size`, `Sequence.depth_size`), looked for among its first
# SIZE_WINDOW frames.
SIZE_PROBES = 5
SIZE_WINDOW = 50


class SequenceError(Sg3dError, ValueError):
    """The sequence as a whole cannot be read (missing folder, unknown layout, no intrinsics);
    front ends show it as one line (ingest knows nothing of them)."""


@dataclass
class Entry:
    name: str
    color: Path
    depth: Path
    timestamp: float
    pose: Optional[np.ndarray] = None      # already parsed (TUM)
    pose_file: Optional[Path] = None       # parsed when the frame is reached (7-Scenes, ScanNet)


class _FileSource:
    """Decodes one frame's files; every failure names the file."""

    __slots__ = ("entry", "seq", "registered")

    def __init__(self, entry: Entry, seq: "Sequence", registered: bool = True):
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
        size = self.seq.depth_size
        if size is not None and (raw.shape[1], raw.shape[0]) != size:
            raise FrameError(self.entry.name, f"{self.entry.depth.name} is {raw.shape[1]}x{raw.shape[0]}, "
                                              f"the sequence's depth images are {size[0]}x{size[1]}")
        depth = raw.astype(np.float32)
        depth *= np.float32(1.0 / self.seq.depth_scale)
        depth[raw == 65535] = 0.0  # the sensor's "no reading" marker, like 0
        return self.seq.registrar(depth) if self.registered else depth


def _parse_pose(entry: Entry) -> np.ndarray:
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
    return rigid(pose)


class Sequence:
    """A posed RGB-D sequence: `len(seq)`, `seq.frames(...)`, `seq.K`, `seq.skipped`."""

    layout = ""
    depth_scale = 1000.0

    def __init__(self, path: Path, entries: list[Entry], K: np.ndarray,
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
        self._motion: Optional[dict[int, str]] = None

    def motion_problems(self) -> dict[int, str]:
        """Frame index -> why its pose is no plausible move of the camera from its neighbours
        (`pose_check.implausible_motion`: a jump or a turn no hand-held or robot camera makes),
        found once over the whole sequence's poses."""
        if getattr(self, "_motion", None) is None:
            poses: list[Optional[np.ndarray]] = []
            for entry in self._entries:
                try:
                    poses.append(_parse_pose(entry))
                except FrameError:
                    poses.append(None)       # named when the frame is reached
            self._motion = implausible_motion(poses, [e.timestamp for e in self._entries],
                                              [e.name for e in self._entries])
        return self._motion or {}

    def _source(self, entry: Entry) -> FrameSource:
        """What decodes one entry's pixels (a bag reader decodes messages instead of files)."""
        return _FileSource(entry, self)

    def _probe_size(self, probes: int = SIZE_PROBES) -> tuple[int, int]:
        """The colour image size most of the first readable frames agree on (one odd image at the
        start must not make every other frame the wrong size)."""
        from collections import Counter

        sizes: Counter = Counter()
        for entry in self._entries[:SIZE_WINDOW]:
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
        self.size_votes = sum(sizes.values())
        return sizes.most_common(1)[0][0]

    @property
    def depth_size(self) -> Optional[tuple[int, int]]:
        """(width, height) of the recording's depth images: the size most of the first readable
        depth files agree on (read from their headers, found once), or None when none is readable.
        A depth image of another size is a damaged frame, never resampled: only a depth camera
        whose size differs from the colour camera's for the whole recording is (`DepthRegistrar`)."""
        if not hasattr(self, "_depth_size"):
            self._depth_size, self.depth_votes = _probe_depth_size(
                [e.depth for e in self._entries[:SIZE_WINDOW] if isinstance(e.depth, Path)])
        return self._depth_size

    def _depth_size_problem(self, entry: Entry) -> Optional[str]:
        """Why the frame's depth file is of another size than the recording's (read from its
        header when the frame is reached, so every frame a build or a map passes is checked, not
        only those whose depth is decoded), or None."""
        path = getattr(entry, "depth", None)
        if not isinstance(path, Path) or not path.is_file():
            return None
        size = self.depth_size
        if size is None:
            return None
        got = _image_header_size(path, decode=False)
        if got is None or got == size:
            return None     # a damaged file is named when it is decoded
        return f"{path.name} is {got[0]}x{got[1]}, the sequence's depth images are {size[0]}x{size[1]}"

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
        problem = self.motion_problems().get(i) or self._depth_size_problem(entry)
        if problem:
            self.skip(entry.name, problem)
            raise FrameError(entry.name, problem)
        frame = Frame(i, None, None, self.K, pose, FrameInfo(entry.timestamp, entry.name, self.image_size,
                                                             self._source(entry), self.skip))
        return frame if lazy else frame.load()

    def unposed_frame(self, i: int) -> Frame:
        """Frame i without its pose (a NaN matrix), lazily decoded, for a recording that carries
        none (`sg3d map` tracks it online); FrameError when its depth is of another size."""
        entry = self._entries[i]
        problem = self._depth_size_problem(entry)
        if problem:
            self.skip(entry.name, problem)
            raise FrameError(entry.name, problem)
        return Frame(i, None, None, self.K, np.full((4, 4), np.nan),
                     FrameInfo(entry.timestamp, entry.name, self.image_size, self._source(entry), self.skip))


def _image_header_size(path: Path, decode: bool = True) -> Optional[tuple[int, int]]:
    """(width, height) of an image file from its PNG header (no decoding), else by decoding it
    (when `decode`); None when it cannot be read."""
    try:
        with open(path, "rb") as f:
            head = f.read(24)
        if head.startswith(PNG_SIGNATURE) and head[12:16] == b"IHDR":
            w, h = struct.unpack(">II", head[16:24])
            return int(w), int(h)
        if not decode:
            return None
        data = path.read_bytes()
    except OSError:
        return None
    if image_problem(data, path.suffix):
        return None
    img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
    return None if img is None else (img.shape[1], img.shape[0])


def _probe_depth_size(paths: list[Path], probes: int = SIZE_PROBES) -> tuple[Optional[tuple[int, int]], int]:
    """The size most of the first `probes` readable depth images agree on (one odd image at the
    start must not make every other frame the wrong size), or None; and how many were read."""
    from collections import Counter

    sizes: Counter = Counter()
    for path in paths:
        size = _image_header_size(path) if path.is_file() else None
        if size is not None:
            sizes[size] += 1
            if sum(sizes.values()) >= probes:
                break
    return (sizes.most_common(1)[0][0] if sizes else None), sum(sizes.values())


def read_matrix(path: Path) -> np.ndarray:
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


def quaternion_to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (qx, qy, qz, qw), normalised first."""
    x, y, z, w = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def numbered_images(folder: Path) -> list[tuple[int, Path]]:
    """(number, path) of the images named by a frame number (``12.jpg``, ``00012.png``), in order."""
    return sorted((int(p.stem), p) for p in folder.iterdir()
                  if p.suffix.lower() in (".jpg", ".jpeg", ".png") and p.stem.isdigit())
