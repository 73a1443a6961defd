"""`sg3d build` names and counts every frame it could not use, wherever it met it (gravity
estimation, frame selection, detection), and keeps decoders' own warnings off stderr."""
from __future__ import annotations

import json
import os

import cv2
import numpy as np
import pytest

from tests.cli_helpers import sg3d


@pytest.fixture(scope="module")
def damaged(kitchen_dir, tmp_path_factory):
    """60 real kitchen frames with five kinds of damage."""
    seq = tmp_path_factory.mktemp("damaged")
    (seq / "camera-intrinsics.txt").write_bytes((kitchen_dir / "camera-intrinsics.txt").read_bytes())
    for i in range(60):
        for ext in ("color.jpg", "depth.png", "pose.txt"):
            (seq / f"frame-{i:06d}.{ext}").write_bytes((kitchen_dir / f"frame-{i:06d}.{ext}").read_bytes())
    cv2.imwrite(str(seq / "frame-000000.color.jpg"), np.zeros((1, 1, 3), np.uint8))        # 1x1 image
    depth = seq / "frame-000059.depth.png"                                                 # truncated depth
    depth.write_bytes(depth.read_bytes()[:3000])
    pose = np.loadtxt(seq / "frame-000020.pose.txt")                                       # a mirror, not a rotation
    pose[:3, 0] *= -1
    np.savetxt(seq / "frame-000020.pose.txt", pose)
    loop = seq / "frame-000030.color.jpg"                                                  # a looping symlink
    loop.unlink()
    os.symlink(loop.name, loop)
    colour = seq / "frame-000040.color.jpg"                                                # truncated JPEG
    colour.write_bytes(colour.read_bytes()[:4000])
    return seq


def test_build_names_every_damaged_frame_and_prints_no_decoder_noise(damaged, tmp_path):
    home = tmp_path / "home"
    out = sg3d(home, "build", str(damaged), "--room", "damaged", "--json", timeout=600)
    try:
        assert out.returncode == 0, out.stderr
        summary = json.loads(out.stdout)
        reasons = {s["frame"]: s["reason"] for s in summary["frames"]["skipped_frames"]}
        assert set(reasons) == {"frame-000000", "frame-000020", "frame-000030", "frame-000040", "frame-000059"}
        assert summary["frames"]["skipped"] == 5
        assert "1x1" in reasons["frame-000000"]
        assert "reflection" in reasons["frame-000020"]
        assert "truncated" in reasons["frame-000040"]
        for noise in ("libpng", "Premature end", "WARN", "Traceback"):
            assert noise not in out.stderr
    finally:
        sg3d(home, "db", "stop")
