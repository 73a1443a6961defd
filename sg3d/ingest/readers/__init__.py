"""Posed RGB-D sequences on disk -> lazily decoded `Frame`s: one module per layout (`seven_scenes`,
`tum`, `scannet`, `open3d`, `plain`), ROS bags (`bag`), what they share (`base`).

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
``trajectory.log``, TUM without ``groundtruth.txt``) opens with `Sequence.has_poses()` false; `sg3d.ingest.poses` estimates them and
`Sequence.use_poses` hands them to the frames.

Depth is delivered as float32 metres registered to the colour image (see `sg3d.ingest.readers.registration`),
raw 0 and 65535 read as 0 = invalid. A bad frame (missing or corrupt image, non-finite or
non-rigid pose, no timestamp match) is skipped and listed in `Sequence.skipped` as
(frame name, reason naming the file); a sequence without intrinsics is a `SequenceError`.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional, Union

from sg3d.ingest.readers import bag as bags
from sg3d.ingest.readers.base import Sequence, SequenceError, quaternion_to_matrix
from sg3d.ingest.readers.open3d import Open3dSequence
from sg3d.ingest.readers.plain import PlainSequence
from sg3d.ingest.readers.registration import Registration
from sg3d.ingest.readers.scannet import ScanNetSequence
from sg3d.ingest.readers.seven_scenes import SEVEN_SCENES_COLOUR, SevenScenesSequence
from sg3d.ingest.readers.tum import TumSequence

__all__ = ["LAYOUTS", "Sequence", "SequenceError", "detect_layout", "open_sequence", "quaternion_to_matrix"]

LAYOUTS = ("7scenes", "tum", "scannet", "open3d", "plain")
_ALIASES = {"3dmatch": "7scenes", "7-scenes": "7scenes", "tum-rgbd": "tum", "sens": "scannet",
            "redwood": "open3d", "folder": "plain"}


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
    if (path / "camera-intrinsics.txt").is_file() or any(SEVEN_SCENES_COLOUR.match(p.name) for p in path.iterdir()):
        return "7scenes"
    raise SequenceError(f"cannot tell the layout of {path}: expected 7-Scenes (frame-NNNNNN.color.jpg), "
                        f"TUM RGB-D (rgb.txt, depth.txt), ScanNet (color/, depth/, pose/, intrinsic/) or "
                        f"Open3D (image/, depth/, trajectory.log, intrinsics JSON) or a plain folder "
                        f"(color/, depth/, intrinsics.txt)")


def open_sequence(path: Union[str, Path], layout: Optional[str] = None,
                  registration: Optional[Registration] = None, **bag_options: Any) -> Sequence:
    """Open a posed RGB-D sequence folder, or a ROS bag (`sg3d.ingest.readers.bag`: a ROS1 .bag, a ROS2 bag
    folder, a bare .mcap or .db3). `layout`: one of LAYOUTS or "rosbag" (auto-detected when None);
    `registration`: depth-to-colour registration (None: the layout's default); `bag_options`:
    `sg3d.ingest.readers.bag.BagOptions` fields (topics, camera/world frame, max_dt), only for bags."""
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
    readers: dict[str, Union[type[SevenScenesSequence], type[TumSequence], type[ScanNetSequence],
                             type[Open3dSequence], type[PlainSequence]]]
    readers = {"7scenes": SevenScenesSequence, "tum": TumSequence, "scannet": ScanNetSequence,
               "open3d": Open3dSequence, "plain": PlainSequence}
    if name not in readers:
        raise SequenceError(f"unknown layout {layout!r}; choose one of {', '.join(LAYOUTS)}")
    return readers[name].open(path, registration=registration)
