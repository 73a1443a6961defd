"""The wheel is the package: built from the project's files (pyproject.toml, README.md, LICENSE,
sg3d/), it holds every module, every Cypher template and every data file of the checkout under
one top-level package, and installed non-editable into a fresh virtual environment it runs the
real CLI from a directory outside the checkout: `--help`, a build of the living room, a question.

Nothing is downloaded: the wheel is built without build isolation and installed with --no-deps
--no-index; the fresh environment sees the project's dependencies through a .pth file naming this
environment's site-packages (a folder a .pth adds is not scanned for .pth files, so the checkout's
editable finder stays inactive there). About a minute, most of it the build."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

from tests.cli_helpers import sg3d_env
from tests.conftest import REPO, SHARED

LIVING = SHARED / "data" / "open3d-livingroom1-micro"
PROJECT_FILES = ("pyproject.toml", "README.md", "LICENSE")


def _run(cmd: list, timeout: float, **kwargs) -> subprocess.CompletedProcess:
    out = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=timeout, **kwargs)
    assert out.returncode == 0, (cmd, out.stdout[-3000:], out.stderr[-3000:])
    return out


def _checkout_files(pattern: str) -> set[str]:
    return {p.relative_to(REPO).as_posix() for p in (REPO / "sg3d").glob(pattern)
            if p.is_file() and "__pycache__" not in p.parts}


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from a copy of the project's files (no build/ or egg-info of the checkout
    can leak in, and nothing is written into the checkout)."""
    root = tmp_path_factory.mktemp("wheel")
    src = root / "src"
    src.mkdir()
    for name in PROJECT_FILES:
        shutil.copy2(REPO / name, src / name)
    shutil.copytree(REPO / "sg3d", src / "sg3d", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index", ".",
          "-w", root / "dist"], timeout=300, cwd=src)
    wheels = list((root / "dist").glob("sg3d-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


def test_the_wheel_holds_every_module_template_and_data_file_under_one_package(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    tops = {n.split("/", 1)[0] for n in names}
    assert {t for t in tops if not t.endswith(".dist-info")} == {"sg3d"}, tops
    assert len([t for t in tops if t.endswith(".dist-info")]) == 1, tops
    cypher = _checkout_files("cypher/*.cypher")
    assert len(cypher) > 100 and cypher <= names, sorted(cypher - names)
    assert len([n for n in names if n.startswith("sg3d/cypher/") and n.endswith(".cypher")]) == len(cypher)
    data = _checkout_files("**/data/**/*")
    assert "sg3d/app/data/samples/kitchen.json" in data and "sg3d/core/data/label_vectors.npy" in data
    assert data <= names, sorted(data - names)
    modules = _checkout_files("**/*.py")
    assert modules <= names, sorted(modules - names)      # a subpackage without __init__.py would be missing
    entry = zipfile.ZipFile(wheel).read(next(n for n in names if n.endswith(".dist-info/entry_points.txt")))
    assert b"sg3d = sg3d.cli:main" in entry


@pytest.fixture(scope="module")
def venv(wheel, tmp_path_factory) -> Path:
    """A fresh virtual environment with the wheel installed (not editable) and this
    environment's site-packages on its path for the dependencies."""
    root = tmp_path_factory.mktemp("venv")
    env = root / "venv"
    _run([sys.executable, "-m", "venv", "--without-pip", env], timeout=120)
    python = env / "bin" / "python"
    _run([sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-index", wheel], timeout=300)
    site = _run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], timeout=60).stdout.strip()
    ours = dict.fromkeys([sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]])
    (Path(site) / "_sg3d_test_dependencies.pth").write_text("".join(f"{p}\n" for p in ours))
    return env


def _env(home: Path) -> dict:
    env = sg3d_env(home)
    for name in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP"):
        env.pop(name, None)
    return env


def test_the_installed_wheel_runs_the_cli_outside_the_checkout(venv, tmp_path):
    if not (LIVING / "trajectory.log").exists():
        pytest.skip("living-room data not found at ../shared/data/open3d-livingroom1-micro (set SG3D_SHARED)")
    cwd, home = tmp_path / "elsewhere", tmp_path / "home"
    cwd.mkdir()
    env, sg3d = _env(home), venv / "bin" / "sg3d"
    probe = ("import json, sys, sg3d, sg3d.graphdb.cypher as c; print(json.dumps({'file': sg3d.__file__, "
             "'cypher': str(c.cypher_dir()), 'editable': [m for m in sys.modules if 'editable' in m] + "
             "[repr(f) for f in sys.meta_path if 'editable' in repr(f).lower()]}))")
    where = json.loads(_run([venv / "bin" / "python", "-c", probe], timeout=120, cwd=cwd, env=env).stdout)
    assert Path(where["file"]).is_relative_to(venv) and not Path(where["file"]).is_relative_to(REPO), where
    assert Path(where["cypher"]).is_relative_to(venv) and where["editable"] == [], where

    assert "sample" in _run([sg3d, "--help"], timeout=120, cwd=cwd, env=env).stdout
    try:
        build = _run([sg3d, "build", LIVING, "--room", "living", "--json"], timeout=600, cwd=cwd, env=env)
        assert json.loads(build.stdout)["frames"]["read"] == 211
        answer = _run([sg3d, "ask", "how many chairs are there?", "--room", "living"], timeout=300, cwd=cwd, env=env)
        assert answer.stdout.strip() == "1 chair", answer.stdout
    finally:
        subprocess.run([sg3d, "db", "stop"], capture_output=True, timeout=120, cwd=cwd, env=env)
    assert os.listdir(cwd) == []                             # the CLI wrote nothing into its working directory
