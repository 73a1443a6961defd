"""The README's first command on a machine with no ../shared: `sg3d sample kitchen` downloads the
real kitchen (its shipped manifest, every file checked) from a mirror served on 127.0.0.1 (never
the internet), and `sg3d build` builds it into a fresh store, from a folder with nothing beside it."""
from __future__ import annotations

import functools
import os
import re
import subprocess
import sys
import threading
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer

import pytest

from tests.cli_helpers import sg3d, sg3d_env
from tests.conftest import REPO

README = REPO / "README.md"


def first_command_after_install() -> str:
    """The sg3d part of the README's first shell line (the install steps have run already)."""
    block = re.search(r"```sh\n(.*?)\n```", README.read_text(encoding="utf-8"), re.S)
    assert block, "the README starts with a shell block"
    steps = [s.strip() for s in block.group(1).splitlines()[0].split("&&")]
    return " && ".join(s for s in steps if s.startswith("sg3d "))


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture
def mirror(kitchen_dir):
    """The folder holding the kitchen, served over HTTP on loopback as a sample mirror."""
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(kitchen_dir.parent)))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()
        httpd.server_close()


def test_the_readme_first_command_downloads_and_builds_the_kitchen(tmp_path, mirror):
    command = first_command_after_install()
    assert "--sample kitchen" in command and "sg3d build" in command, command
    cwd = tmp_path / "nowhere" / "cwd"          # no ../shared/data beside it
    cwd.mkdir(parents=True)
    home = tmp_path / "home"
    env = sg3d_env(home, SG3D_SAMPLE_URL=mirror, SG3D_CACHE=str(tmp_path / "cache"),
                   PATH=os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", ""))
    try:
        out = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True, timeout=900)
        assert out.returncode == 0, out.stderr[-2000:]
        sample = tmp_path / "cache" / "samples" / "7scenes-redkitchen"
        assert len(list(sample.glob("frame-*.pose.txt"))) == 1000      # downloaded whole, into the cache
        answer = sg3d(home, "ask", "how many chairs are there?", "--room", "kitchen")
        assert answer.returncode == 0 and re.match(r"\d+ chairs?", answer.stdout.strip()), answer.stdout
    finally:
        sg3d(home, "db", "stop")


def test_offline_the_readme_first_command_ends_with_one_line_naming_the_way_out(tmp_path):
    command = first_command_after_install()
    cwd = tmp_path / "nowhere" / "cwd"          # no ../shared/data beside it
    cwd.mkdir(parents=True)
    env = sg3d_env(tmp_path / "home", SG3D_SAMPLE_URL="http://127.0.0.1:9", SG3D_CACHE=str(tmp_path / "cache"),
                   PATH=os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", ""))
    out = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 2, (out.returncode, out.stderr[-2000:])
    errors = [line for line in out.stderr.splitlines() if line.lower().startswith("error")]
    assert len(errors) == 1 and out.stderr.strip().splitlines()[-1] == errors[0], out.stderr
    assert "SG3D_SAMPLE_URL" in errors[0] and "SG3D_SAMPLES" in errors[0] and "../shared/data" in errors[0]
    assert not (tmp_path / "home").exists() or not (tmp_path / "home" / "databases").exists()   # no store started
    assert not list((tmp_path / "cache").rglob("*.partial"))
