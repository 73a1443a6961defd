"""Write a recorded sequence into a folder at a camera's rate, as a recorder would, for
`sg3d map` to follow: `python -m benchmarks.live_writer SRC DST [--fps 30] [--stop N]`.

Each file is written under a temporary name and renamed (what a recorder should do, see
`sg3d.ingest.readers.follow`); the frame's colour image goes last, so a listed frame is whole.
Two layouts: 7-Scenes/3DMatch (per-frame files) and Open3D (image/, depth/, and trajectory.log
rewritten with the poses so far). `--no-poses` writes no pose file (a camera without tracking:
`sg3d map` tracks such a folder itself). Prints nothing; exits when every frame is written.
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import time
from pathlib import Path
from typing import Callable, Optional

SEVEN = re.compile(r"^(frame-\d+)\.color\.(jpg|jpeg|png)$", re.IGNORECASE)


def _put(src: Path, dst: Path) -> None:
    tmp = dst.with_name("." + dst.name + ".part")
    shutil.copyfile(src, tmp)
    os.replace(tmp, dst)


def _put_text(text: str, dst: Path) -> None:
    tmp = dst.with_name("." + dst.name + ".part")
    tmp.write_text(text)
    os.replace(tmp, dst)


def seven_scenes_frames(src: Path, poses: bool = True) -> list[list[tuple[Path, str]]]:
    """Per frame: (source file, name in the destination), colour last."""
    out = []
    for p in sorted(src.iterdir()):
        m = SEVEN.match(p.name)
        if m:
            stem = m.group(1)
            files = [(src / f"{stem}.depth.png", f"{stem}.depth.png")]
            if poses:
                files.append((src / f"{stem}.pose.txt", f"{stem}.pose.txt"))
            out.append([f for f in files if f[0].is_file()] + [(p, p.name)])
    return out


# A frame held back (`write_live`'s `hold`) waits this much longer: well under any idle stop.
HOLD_S = 0.5


def write_live(src: Path, dst: Path, fps: float = 30.0, stop: Optional[int] = None, start_delay: float = 0.0,
               poses: bool = True, skip: frozenset = frozenset(),
               hold: Optional[Callable[[int], bool]] = None) -> int:
    """Write SRC's frames into DST at `fps` frames per second (without pose files unless `poses`;
    the frames numbered in `skip` are left out, as a camera drops them); returns the frames written.
    `hold(k)` True: frame k and those after it come HOLD_S later (a test lets a reader that a
    loaded machine slowed catch up, without a pause it would take for the end of the recording)."""
    src, dst = Path(src), Path(dst)
    dst.mkdir(parents=True, exist_ok=True)
    if start_delay:
        time.sleep(start_delay)
    t0 = time.monotonic()
    if (src / "trajectory.log").is_file():
        return _write_open3d(src, dst, fps, stop, t0, poses, skip)
    for name in ("camera-intrinsics.txt",):
        if (src / name).is_file():
            _put(src / name, dst / name)
    frames = seven_scenes_frames(src, poses)[:stop]
    held = 0.0
    for k, files in enumerate(frames):
        _wait(t0 + k / fps + held)
        if hold is not None and hold(k):
            held += HOLD_S
            _wait(t0 + k / fps + held)
        if k in skip:
            continue
        for s, name in files:
            _put(s, dst / name)
    return len(frames)


def _write_open3d(src: Path, dst: Path, fps: float, stop: Optional[int], t0: float, poses: bool = True,
                  skip: frozenset = frozenset()) -> int:
    for p in src.glob("*.json"):
        _put(p, dst / p.name)
    (dst / "image").mkdir(exist_ok=True)
    (dst / "depth").mkdir(exist_ok=True)
    blocks = (src / "trajectory.log").read_text().strip().splitlines()
    trajectory = ["\n".join(blocks[i:i + 5]) for i in range(0, len(blocks), 5)]
    images = sorted((src / "image").iterdir())[:stop]
    depths = {p.stem: p for p in (src / "depth").iterdir()}
    for k, img in enumerate(images):
        _wait(t0 + k / fps)
        if k in skip:
            continue
        _put(depths[img.stem], dst / "depth" / depths[img.stem].name)
        if poses:
            _put_text("\n".join(trajectory[:k + 1]) + "\n", dst / "trajectory.log")
        _put(img, dst / "image" / img.name)
    return len(images)


def _wait(until: float) -> None:
    delay = until - time.monotonic()
    if delay > 0:
        time.sleep(delay)


def main(argv: Optional[list[str]] = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src", type=Path)
    ap.add_argument("dst", type=Path)
    ap.add_argument("--fps", type=float, default=30.0)
    ap.add_argument("--stop", type=int, default=None, help="write only the first N frames")
    ap.add_argument("--start-delay", type=float, default=0.0)
    ap.add_argument("--no-poses", action="store_true", help="write no pose files (a camera without tracking)")
    a = ap.parse_args(argv)
    write_live(a.src, a.dst, a.fps, a.stop, a.start_delay, poses=not a.no_poses)


if __name__ == "__main__":
    main()
