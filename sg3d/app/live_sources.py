"""Which live source a `sg3d map SOURCE` names, and opening it.

- a folder being written (any layout sg3d reads, or a finished ROS 2 bag folder):
  `sg3d.ingest.readers.follow.FolderFollower`; it can be read again at the end, so the final
  graph is the one `sg3d build` gives;
- ``realsense``, ``realsense:SERIAL``, ``realsense:FILE.bag|.db3``: a RealSense camera or
  recording (`sg3d.ingest.readers.realsense`);
- ``FILE.mcap``, or a ROS 2 bag folder still being recorded (``*.mcap`` files, no
  ``metadata.yaml`` yet: the first one is followed): `sg3d.ingest.readers.mcap_follow`.

Sources without poses (a folder without pose files, a RealSense; an MCAP without /tf or a pose
topic) are wrapped in
`sg3d.ingest.poses.online.OnlinePoses`. A camera or stream cannot be read again: such sources
have ``seq = None`` and their final graph is the live evidence.
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

from sg3d.app.errors import MapError


class SourceError(MapError):
    """A `sg3d map` SOURCE that names nothing that can be followed, or cannot be opened."""


def _recorded_mcap(path: Path) -> Optional[Path]:
    """The first .mcap file of a ROS 2 bag folder being recorded (no metadata.yaml yet)."""
    if not path.is_dir() or (path / "metadata.yaml").exists():
        return None
    files = sorted(path.glob("*.mcap"))
    return files[0] if files else None


def source_kind(source) -> str:
    """"folder", "realsense" or "mcap" for a SOURCE; SourceError when it names none of them."""
    from sg3d.ingest.readers.realsense import is_realsense

    text = str(source)
    if is_realsense(text):
        return "realsense"
    path = Path(text).expanduser()
    if path.suffix.lower() == ".mcap" and not path.is_dir():
        return "mcap"
    if _recorded_mcap(path) is not None:
        return "mcap"
    if path.is_dir():
        return "folder"
    raise SourceError(f"source folder not found: {source} (sg3d map follows a folder being written, realsense[:SERIAL|:FILE.bag], "
                      f"or an MCAP file being recorded)")


def open_live_source(source, layout: Optional[str] = None):
    """The LiveSource SOURCE names (module docstring); SourceError when it cannot be opened."""
    from sg3d.ingest.poses.online import OnlinePoses
    from sg3d.ingest.readers.base import SequenceError
    from sg3d.ingest.readers.follow import FolderFollower

    kind = source_kind(source)
    if kind == "folder":      # tracked online when its frames turn out to carry no poses
        return OnlinePoses(FolderFollower(Path(source), layout))
    try:
        if kind == "realsense":
            from sg3d.ingest.readers.realsense import RealSenseSource

            return OnlinePoses(RealSenseSource(str(source)))
        from sg3d.ingest.readers.mcap_follow import McapFollower

        path = Path(str(source)).expanduser()
        return OnlinePoses(McapFollower(_recorded_mcap(path) or path))
    except SequenceError as exc:
        raise SourceError(str(exc))
