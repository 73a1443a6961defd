"""`sg3d map` checks and names bad frames as `sg3d build` does: 60 real kitchen frames with ten
kinds of damage, built once and mapped once while a writer thread writes them into a folder;
the two name the same frames for the same reasons, and the map's `--json` lists them by reason."""
from __future__ import annotations

import json
import os
import shutil
import threading
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from tests.cli_helpers import sg3d

# frame -> what is wrong with it (and the words its reason must hold)
DAMAGE = {
    "frame-000000": "1x1",              # a 1x1 colour image
    "frame-000010": "320x240",          # a depth image of another size than the recording's
    "frame-000015": "320x240",          # a colour image of another size
    "frame-000020": "reflection",       # a mirrored pose
    "frame-000025": "jumps 5 m",        # a pose 5 m off its neighbours
    "frame-000030": "missing",          # a colour image that is a looping symlink
    "frame-000040": "truncated",        # a truncated JPEG
    "frame-000045": "missing",          # no pose file
    "frame-000050": "not finite",       # a NaN in the pose
    "frame-000059": "truncated",        # a truncated depth PNG
}


def _damage(seq: Path) -> None:
    def pose(i: int) -> tuple[Path, np.ndarray]:
        return seq / f"frame-{i:06d}.pose.txt", np.loadtxt(seq / f"frame-{i:06d}.pose.txt")

    cv2.imwrite(str(seq / "frame-000000.color.jpg"), np.zeros((1, 1, 3), np.uint8))
    d = cv2.imread(str(seq / "frame-000010.depth.png"), cv2.IMREAD_UNCHANGED)
    cv2.imwrite(str(seq / "frame-000010.depth.png"), cv2.resize(d, (320, 240), interpolation=cv2.INTER_NEAREST))
    c = cv2.imread(str(seq / "frame-000015.color.jpg"))
    cv2.imwrite(str(seq / "frame-000015.color.jpg"), cv2.resize(c, (320, 240)))
    path, p = pose(20)
    p[:3, 0] *= -1
    np.savetxt(path, p)
    path, p = pose(25)
    p[0, 3] += 5.0
    np.savetxt(path, p)
    loop = seq / "frame-000030.color.jpg"
    loop.unlink()
    os.symlink(loop.name, loop)
    colour = seq / "frame-000040.color.jpg"
    colour.write_bytes(colour.read_bytes()[:4000])
    (seq / "frame-000045.pose.txt").unlink()
    path, p = pose(50)
    p[0, 3] = np.nan
    np.savetxt(path, p)
    depth = seq / "frame-000059.depth.png"
    depth.write_bytes(depth.read_bytes()[:3000])


@pytest.fixture(scope="module")
def damaged(kitchen_dir, tmp_path_factory):
    seq = tmp_path_factory.mktemp("damaged")
    (seq / "camera-intrinsics.txt").write_bytes((kitchen_dir / "camera-intrinsics.txt").read_bytes())
    for i in range(60):
        for ext in ("color.jpg", "depth.png", "pose.txt"):
            (seq / f"frame-{i:06d}.{ext}").write_bytes((kitchen_dir / f"frame-{i:06d}.{ext}").read_bytes())
    _damage(seq)
    return seq


def _write_live(src: Path, dst: Path, fps: float, delay: float) -> None:
    """Write src's frames into dst as a recorder would (depth, pose, then colour; each renamed
    into place), symlinks as symlinks."""
    time.sleep(delay)
    shutil.copyfile(src / "camera-intrinsics.txt", dst / "camera-intrinsics.txt")
    t0 = time.monotonic()
    for k in range(60):
        time.sleep(max(0.0, t0 + k / fps - time.monotonic()))
        for ext in ("depth.png", "pose.txt", "color.jpg"):
            s, d = src / f"frame-{k:06d}.{ext}", dst / f"frame-{k:06d}.{ext}"
            if s.is_symlink():
                os.symlink(os.readlink(s), d)
            elif s.exists():
                tmp = d.with_name("." + d.name + ".part")
                shutil.copyfile(s, tmp)
                os.replace(tmp, d)


def test_map_names_the_bad_frames_a_build_names(damaged, tmp_path):
    home = tmp_path / "home"
    live = tmp_path / "live"
    live.mkdir()
    try:
        out = sg3d(home, "build", str(damaged), "--room", "built", "--json", timeout=600)
        assert out.returncode == 0, out.stderr
        built = {s["frame"]: s["reason"] for s in json.loads(out.stdout)["frames"]["skipped_frames"]}
        assert set(built) == set(DAMAGE), built
        for frame, words in DAMAGE.items():
            assert words in built[frame], (frame, built[frame])

        writer = threading.Thread(target=_write_live, args=(damaged, live, 10.0, 3.0), daemon=True)
        writer.start()
        out = sg3d(home, "map", str(live), "--room", "mapped", "--stop-when-idle", "2", "--json", timeout=600)
        writer.join()
        assert out.returncode == 0, out.stderr
        frames = json.loads(out.stdout)["frames"]
        mapped = {s["frame"]: s["reason"] for kind in frames["skipped_by_reason"] for s in kind["frames"]}
        assert mapped == built
        assert frames["skipped"] == len(built) == sum(kind["count"] for kind in frames["skipped_by_reason"])
        kinds = {kind["reason"] for kind in frames["skipped_by_reason"]}
        assert "depth.png is truncated (no PNG end chunk)" in kinds and "missing pose.txt" in kinds, kinds
        for noise in ("libpng", "Premature end", "WARN", "Traceback"):
            assert noise not in out.stderr
    finally:
        sg3d(home, "db", "stop")
