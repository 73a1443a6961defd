"""The embedded store's database files: watched while the daemon runs, and recorded outside the
store folder so that a store whose files went is never started again as an empty one.

ArcadeDB keeps each type's records in `*.bucket` files, property names in `dictionary.*.dict` and
the types in `schema.json`; it never deletes those while it runs (sg3d drops no type), so any of
them missing is damage (index files `*.umtidx` / `*.numtidx` are replaced when compacted and WAL
files `*.wal` rotate: not watched; a lost index is found by `sg3d db check`). A file deleted under
a running store takes every write acknowledged into it with it at the next restart: the daemon
stops instead (`sg3d.graphdb.daemon`).
"""
from __future__ import annotations

import json
import os
import re
import stat
import time
from pathlib import Path
from typing import Optional

# The files ArcadeDB never deletes from a database folder while the database exists.
KEPT_FILES = re.compile(r"(\.bucket|\.dict)$|^schema\.json$")
RECORD_SUFFIX = ".sg3d-database"


def record_path(store_dir: Path) -> Path:
    """Where the record that a database was created lives: beside the store folder, not in it
    (`rm -rf` of the store folder, or of its database, leaves it)."""
    return store_dir.parent / f".{store_dir.name}{RECORD_SUFFIX}"


def kept_files(database_dir: Path) -> set[str]:
    """The names of the database's files ArcadeDB never deletes while it runs (`KEPT_FILES`)."""
    with os.scandir(database_dir) as entries:
        return {e.name for e in entries if KEPT_FILES.search(e.name)}


def deleted_open_files(folder: Path) -> list[str]:
    """Files under `folder` this process holds open that were deleted (Linux: the fd's link ends
    ' (deleted)'); empty elsewhere."""
    prefix, out = str(folder) + os.sep, []
    try:
        fds = os.listdir("/proc/self/fd")
    except OSError:
        return []
    for fd in fds:
        try:
            target = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        if target.startswith(prefix) and target.endswith(" (deleted)"):
            out.append(target[len(prefix):-len(" (deleted)")])
    return out


def read_record(path: Path) -> Optional[dict]:
    """The record at `path` ({"created": ..., "files": [...], "lost": why?}), {} when it is there
    but unreadable (still: a database existed), None when there is none of this user's (another
    user's file or a link in a shared folder is never trusted)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid():
            return None
        data = json.loads(os.read(fd, 1 << 22) or b"{}")
        return data if isinstance(data, dict) else {}
    except ValueError:
        return {}
    finally:
        os.close(fd)


def write_record(path: Path, data: dict) -> Optional[str]:
    """Write the record (0600, never through a link, only this user's file); why not, or None."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0), 0o600)
    except OSError as exc:
        return f"cannot write {path}: {exc.strerror or exc}"
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid():
            return f"cannot write {path}: it is not this user's file"
        text = json.dumps(data).encode()
        os.pwrite(fd, text, 0)
        os.ftruncate(fd, len(text))
        return None
    finally:
        os.close(fd)


def gone_from(record: dict, database_dir: Path) -> Optional[str]:
    """Why the database a `record` says existed is gone: its folder or some of its kept files are
    missing (deleted with the store folder, by a tmp cleaner, by hand), or it was lost while the
    daemon ran. None: its files are there."""
    if record.get("lost"):
        return str(record["lost"])
    created = record.get("created") or "earlier"
    if not database_dir.is_dir():
        return f"the store's database (created {created}) is gone: its folder {database_dir} is not there"
    try:
        missing = sorted(set(record.get("files") or []) - kept_files(database_dir))
    except OSError as exc:
        return f"the store's database folder {database_dir} cannot be read ({exc.strerror or exc})"
    if missing:
        shown = ", ".join(missing[:3]) + (f" and {len(missing) - 3} more" if len(missing) > 3 else "")
        return (f"{len(missing)} file(s) of the store's database (created {created}) are gone from "
                f"{database_dir}: {shown}")
    return None


class FileWatch:
    """The daemon's watch over its database folder: the folder itself (deleted or replaced), the
    kept files (deleted: missing at two looks in a row, since ArcadeDB may rewrite schema.json by
    renaming, or deleted while the store holds them open); and the record beside the store folder,
    kept up to date with the kept files' names."""

    def __init__(self, database_dir: Path, record: Path):
        self.database_dir, self.record = database_dir, record
        self.inode = database_dir.stat().st_ino
        self.files = kept_files(database_dir)
        self.missing: set[str] = set()
        old = read_record(record) or {}
        self.data = {"store": str(database_dir), "created": old.get("created") or time.strftime("%Y-%m-%d %H:%M:%S"),
                     "files": sorted(self.files)}
        self.problem = write_record(record, self.data)   # said once in the log; the watch goes on

    def lost(self) -> Optional[str]:
        """Why the store can no longer keep what it acknowledges, or None (one look)."""
        when = time.strftime("%Y-%m-%d %H:%M:%S")
        try:
            if self.database_dir.stat().st_ino != self.inode:
                return f"the store's database folder {self.database_dir} was replaced while the store ran ({when})"
            now = kept_files(self.database_dir)
        except FileNotFoundError:
            return f"the store's database folder {self.database_dir} vanished while the store ran ({when})"
        except OSError as exc:
            return f"the store's database folder {self.database_dir} cannot be read ({exc.strerror or exc}; {when})"
        # index files are closed before they are deleted when compacted, but only the kept files'
        # deletion is certain damage: a deleted index is found by `db check` after the restart
        deleted = [name for name in deleted_open_files(self.database_dir) if KEPT_FILES.search(name)]
        gone = (self.files - now) & self.missing
        if deleted or gone:
            names = sorted(set(deleted) | gone)
            return (f"{len(names)} file(s) of the store's database were deleted while the store ran ({when}): "
                    f"{', '.join(names[:3])}" + (f" and {len(names) - 3} more" if len(names) > 3 else ""))
        self.missing = self.files - now
        if now - self.files:
            self.files |= now
            self.data["files"] = sorted(self.files)
            write_record(self.record, self.data)
        return None

    def mark_lost(self, why: str) -> None:
        """Say `why` in the record too: the home (and its lost mark) may have gone with the files."""
        write_record(self.record, {**self.data, "lost": why})
