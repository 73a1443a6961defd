"""Running the real `sg3d` CLI in a fresh process, and checking its one-line errors."""
from __future__ import annotations

import os
import subprocess
import sys


def sg3d_env(home, **env) -> dict:
    """The environment of an `sg3d` process that uses the store under `home` only: no SG3D_*
    setting of the caller's shell leaks in."""
    full = {k: v for k, v in os.environ.items() if not k.startswith("SG3D_")}
    full.update(SG3D_HOME=str(home), **env)
    return full


def sg3d(home, *args, timeout=900, **env):
    """Run `sg3d ARGS` to completion (the timeout is a safety net for a hung build)."""
    return subprocess.run([sys.executable, "-m", "sg3d", *map(str, args)], capture_output=True, text=True,
                          env=sg3d_env(home, **env), timeout=timeout)


def one_error_line(out) -> str:
    assert out.returncode == 2, (out.returncode, out.stdout, out.stderr)
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].lower().startswith("error"), out.stderr
    assert "Traceback" not in out.stderr
    return lines[0]
