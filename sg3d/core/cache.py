"""sg3d's cache folder: what is worked out once per machine and kept (label vectors, the question
parser's tables, the common-word list), never anything that cannot be made again.

SG3D_CACHE, else SG3D_HOME/sg3d-cache (SG3D_HOME keeps everything of one installation together:
store, history, this cache), else the user cache directory.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Optional


def cache_folder() -> Path:
    """The cache folder (not made here)."""
    home = os.environ.get("SG3D_HOME")
    if os.environ.get("SG3D_CACHE"):
        return Path(os.environ["SG3D_CACHE"]).expanduser()
    if home:
        return Path(home).expanduser() / "sg3d-cache"
    from platformdirs import user_cache_dir

    return Path(user_cache_dir("sg3d", appauthor=False))


def writable_cache_folder() -> Optional[Path]:
    """The cache folder, made if needed; None where it cannot be made or written (a read-only home):
    callers then work without a cache."""
    folder = cache_folder()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK) else None


def write_atomically(path: Path, data: bytes) -> None:
    """Write `data` to `path` through a temporary file in the same folder and a rename, so that a
    process reading the cache meanwhile finds the whole file or none (never an empty one)."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
