"""`sg3d sample`: a five-file sample of real kitchen files, served by a real HTTP server on
127.0.0.1 (never the internet), downloaded by the real CLI in a subprocess: the folder it prints
holds exactly the sample's files, a corrupted file is refused and not kept, a killed download
leaves no folder that looks complete and resumes with only what is missing, and a verifying local
copy is used in place."""
from __future__ import annotations

import functools
import json
import os
import shutil
import subprocess
import sys
import threading
import time
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from tests.cli_helpers import one_error_line, sg3d_env
from tests.conftest import KITCHEN

FILES = ["camera-intrinsics.txt", "frame-000000.color.jpg", "frame-000000.depth.png", "frame-000000.pose.txt",
         "frame-000001.pose.txt"]
FOLDER = "mini-kitchen"
HELD = "frame-000000.color.jpg"      # the file the killed download is stuck on


def _need_kitchen() -> None:
    if not all((KITCHEN / name).exists() for name in FILES):
        pytest.skip("real kitchen data not found at ../shared/data/7scenes-redkitchen (set SG3D_SHARED): "
                    "the test sample is made of its files")


class _Server:
    """A real HTTP server over `root` on 127.0.0.1 that records the paths asked for, can hold a
    file until released and can answer 503 once for a file."""

    def __init__(self, root: Path) -> None:
        self.requests: list[str] = []
        self.holds: dict[str, threading.Event] = {}
        self.fail_once: set[str] = set()
        self.fail_always: set[str] = set()
        server = self

        class Handler(SimpleHTTPRequestHandler):
            def do_GET(self):
                name = self.path.rsplit("/", 1)[-1]
                server.requests.append(name)
                if name in server.fail_once or name in server.fail_always:
                    server.fail_once.discard(name)
                    self.send_error(503, "try again")
                    return
                if name in server.holds:
                    server.holds[name].wait(60)
                try:
                    super().do_GET()
                except (BrokenPipeError, ConnectionResetError):
                    pass

            def log_message(self, *args):
                pass

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Handler, directory=str(root)))
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}"
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)

    def release(self) -> None:
        for event in self.holds.values():
            event.set()


@pytest.fixture
def mini(tmp_path):
    """The five-file sample: its manifest, the served mirror (<root>/<folder>/<file>), the HTTP
    server, a cache and a working directory with no ../shared beside it."""
    _need_kitchen()
    from sg3d.app.samples import describe_folder, manifest_text

    mirror = tmp_path / "mirror" / FOLDER
    mirror.mkdir(parents=True)
    for name in FILES:
        shutil.copyfile(KITCHEN / name, mirror / name)
    manifest = tmp_path / "mini.json"
    meta = {"name": "mini", "folder": FOLDER, "title": "five kitchen files", "url": "http://127.0.0.1:9/unused/",
            "source": "tests", "licence": "for tests only", "licence_note": "note: LICENCE-NOTE-OF-MINI"}
    manifest.write_text(manifest_text(meta, describe_folder(mirror)), encoding="utf-8")
    server = _Server(mirror.parent)
    server.thread.start()
    work = tmp_path / "work" / "cwd"
    work.mkdir(parents=True)
    ctx = {"tmp": tmp_path, "mirror": mirror, "manifest": manifest, "server": server, "cwd": work,
           "cache": tmp_path / "cache", "final": tmp_path / "cache" / "samples" / FOLDER}
    try:
        yield ctx
    finally:
        server.release()
        server.httpd.shutdown()
        server.httpd.server_close()


def _env(mini, **extra) -> dict:
    given = {"SG3D_SAMPLE_MANIFEST": str(mini["manifest"]), "SG3D_SAMPLE_URL": mini["server"].url,
             "SG3D_CACHE": str(mini["cache"])}
    return sg3d_env(mini["tmp"] / "home", **{**given, **extra})


def _last_error_line(out) -> str:
    """The one error line a failed download ends with (after its notes and its bar, on stderr)."""
    assert out.returncode == 2, (out.returncode, out.stdout, out.stderr)
    errors = [line for line in out.stderr.splitlines() if line.lower().startswith("error")]
    assert len(errors) == 1 and out.stderr.strip().splitlines()[-1] == errors[0], out.stderr
    assert "Traceback" not in out.stderr
    return errors[0]


def _sample(mini, *args, **extra) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "sg3d", "sample", *args], cwd=mini["cwd"], capture_output=True,
                          text=True, env=_env(mini, **extra), timeout=120)


def _same_files(folder: Path, mirror: Path) -> bool:
    return sorted(os.listdir(folder)) == sorted(FILES) and \
        all((folder / n).read_bytes() == (mirror / n).read_bytes() for n in FILES)


def test_a_download_prints_only_its_folder_which_holds_exactly_the_sample(mini):
    out = _sample(mini, "mini")
    assert out.returncode == 0, out.stderr
    assert out.stdout == f"{mini['final']}\n"               # `sg3d build "$(sg3d sample mini)"` gets the path
    assert _same_files(mini["final"], mini["mirror"])       # nothing extra: no .part, no note, no stamp
    assert os.listdir(mini["cache"] / "samples") == [FOLDER]   # the .partial folder was renamed
    assert sorted(mini["server"].requests) == sorted(FILES)
    assert "LICENCE-NOTE-OF-MINI" in out.stderr             # the licence note before the first download
    again = _sample(mini, "mini", "--json")
    assert again.returncode == 0, again.stderr
    found = json.loads(again.stdout)
    assert (found["origin"], found["path"], found["downloaded_bytes"]) == ("cache", str(mini["final"]), 0)
    assert len(mini["server"].requests) == len(FILES)       # the cached copy verified: nothing fetched
    assert "LICENCE-NOTE-OF-MINI" not in again.stderr


def test_a_corrupted_file_is_refused_in_one_line_and_not_kept(mini):
    bad = mini["mirror"] / "frame-000000.pose.txt"
    bad.write_bytes(bad.read_bytes().replace(b"9", b"8", 1))
    out = _sample(mini, "mini")
    assert out.returncode == 2, out.stderr
    errors = [line for line in out.stderr.splitlines() if line.lower().startswith("error")]
    assert len(errors) == 1 and out.stderr.strip().splitlines()[-1] == errors[0], out.stderr   # after the bar
    assert "Traceback" not in out.stderr
    line = errors[0]
    assert "frame-000000.pose.txt" in line and "SHA-256" in line and "deleted" in line
    assert not mini["final"].exists()
    partial = mini["cache"] / "samples" / f"{FOLDER}.partial"
    assert not partial.exists() or not any(p.name.startswith("frame-000000.pose.txt") for p in partial.iterdir())


def test_a_killed_download_leaves_no_complete_looking_folder_and_resumes(mini):
    server = mini["server"]
    server.holds[HELD] = threading.Event()
    partial = mini["cache"] / "samples" / f"{FOLDER}.partial"
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "sample", "mini"], cwd=mini["cwd"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=_env(mini))
    try:
        deadline = time.monotonic() + 90
        others = [n for n in FILES if n != HELD]
        while not (partial.is_dir() and all((partial / n).exists() for n in others)):
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate(timeout=5)
            time.sleep(0.1)
        assert HELD in server.requests
        proc.kill()                                          # SIGKILL: nothing of sg3d runs after this
        proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
        server.release()
    assert not mini["final"].exists()                        # only the .partial folder is there
    assert not (partial / HELD).exists()
    server.requests.clear()
    out = _sample(mini, "mini", "--json")
    assert out.returncode == 0, out.stderr
    assert server.requests == [HELD]                        # the verified files were kept, not fetched again
    assert json.loads(out.stdout)["downloaded_bytes"] == (mini["mirror"] / HELD).stat().st_size
    assert _same_files(mini["final"], mini["mirror"]) and not partial.exists()


def test_a_local_copy_that_verifies_is_used_in_place_and_one_that_does_not_is_not(mini):
    shared = mini["tmp"] / "work" / "shared" / "data" / FOLDER     # ../shared/data/<folder> from the cwd
    shutil.copytree(mini["mirror"], shared)
    out = _sample(mini, "mini")
    assert out.returncode == 0, out.stderr
    assert out.stdout == f"{shared}\n"
    assert mini["server"].requests == [] and not mini["cache"].exists()

    elsewhere = mini["tmp"] / "elsewhere"                        # $SG3D_SAMPLES/<folder> comes first
    shutil.copytree(mini["mirror"], elsewhere / FOLDER)
    out = _sample(mini, "mini", SG3D_SAMPLES=str(elsewhere))
    assert out.returncode == 0 and out.stdout == f"{elsewhere / FOLDER}\n", out.stderr

    (shared / "frame-000001.pose.txt").write_text("not the pose\n")
    out = _sample(mini, "mini")
    assert out.returncode == 0, out.stderr
    assert out.stdout == f"{mini['final']}\n"                  # downloaded instead
    assert "is not used" in out.stderr and "frame-000001.pose.txt" in out.stderr
    assert (shared / "frame-000001.pose.txt").read_text() == "not the pose\n"   # a local copy is never written


def test_an_unknown_name_is_one_line_listing_the_known_ones(mini):
    line = one_error_line(_sample(mini, "no-such-sample"))
    assert "no-such-sample" in line and "kitchen" in line and "mini" in line
    listed = _sample(mini, "--list", "--json")
    assert listed.returncode == 0, listed.stderr
    rows = {r["name"]: r for r in json.loads(listed.stdout)}
    assert rows["kitchen"]["files"] == 3002 and "non-commercial" in rows["kitchen"]["licence"]
    assert rows["mini"]["bytes"] == sum((mini["mirror"] / n).stat().st_size for n in FILES)
    assert mini["server"].requests == []


def test_a_failed_request_is_retried(mini):
    from sg3d.app.samples import Places, locate_sample

    mini["server"].fail_once.add("camera-intrinsics.txt")
    found = locate_sample("mini", Places(manifests=[mini["manifest"]], cache=mini["cache"], base_url=mini["server"].url,
                                         local_roots=[]))
    assert found.origin == "download" and _same_files(found.path, mini["mirror"])
    assert mini["server"].requests.count("camera-intrinsics.txt") == 2


def test_the_shipped_kitchen_manifest_matches_the_real_kitchen(kitchen_dir):
    """The manifest every download is checked against is that of the shared copy, which matches
    andyzeng/tsdf-fusion-python's data/ at the pinned commit file for file."""
    from sg3d.app.samples import get_sample, unverified

    sample = get_sample("kitchen", manifests=[])
    assert sample.folder == kitchen_dir.name and len(sample.files) == 3 * 1000 + 2
    assert {f"frame-{i:06d}.{kind}" for i in range(1000) for kind in ("color.jpg", "depth.png", "pose.txt")} \
        <= set(sample.files)
    assert "1e14d81c7f1c04ecc8a92a1dcd6214222d7d2c00" in sample.url
    assert unverified(kitchen_dir, sample) == []


def test_a_manifest_naming_a_path_instead_of_a_file_is_refused(tmp_path):
    from sg3d.app.samples import SampleError, load_manifest, manifest_text

    meta = {"name": "odd", "folder": "odd", "title": "t", "url": "http://127.0.0.1:9/", "source": "s",
            "licence": "l", "licence_note": "n"}
    bad = tmp_path / "odd.json"
    bad.write_text(manifest_text(meta, {"../outside.txt": (1, "0" * 64)}))
    with pytest.raises(SampleError, match="plain names"):
        load_manifest(bad)


def test_offline_it_is_one_line_naming_the_ways_out_and_leaves_no_folder(mini):
    out = _sample(mini, "mini", SG3D_SAMPLE_URL="http://127.0.0.1:9")      # nothing listens there
    line = _last_error_line(out)
    assert out.stdout == ""                  # `sg3d build "$(sg3d sample mini)"` gets nothing
    assert "SG3D_SAMPLE_URL" in line and "SG3D_SAMPLES" in line and "../shared/data" in line, line
    assert "kept" not in line and "run again" not in line, line        # nothing was verified
    assert not (mini["cache"] / "samples").exists() or os.listdir(mini["cache"] / "samples") == []


def test_a_download_cut_short_says_how_many_verified_files_are_kept(mini):
    mini["server"].fail_always.add("frame-000001.pose.txt")               # 503, every time
    line = _last_error_line(_sample(mini, "mini"))
    assert "4 files verified so far are kept" in line and "run again" in line, line
    partial = mini["cache"] / "samples" / f"{FOLDER}.partial"
    assert sorted(os.listdir(partial)) == sorted(set(FILES) - {"frame-000001.pose.txt"})


def test_a_mirror_serving_a_bad_file_is_named_not_retried_in_vain(mini):
    bad = mini["mirror"] / "frame-000000.pose.txt"
    bad.write_bytes(bad.read_bytes().replace(b"9", b"8", 1))
    line = _last_error_line(_sample(mini, "mini"))
    assert "run again" not in line and mini["server"].url in line and "SG3D_SAMPLE_URL" in line, line


def test_a_repair_says_so_before_it_starts_and_counts_the_bytes_it_fetches(mini):
    assert _sample(mini, "mini").returncode == 0
    broken = mini["final"] / "frame-000000.depth.png"
    broken.write_bytes(b"not a png")
    out = _sample(mini, "mini")
    assert out.returncode == 0, out.stderr
    assert "repairing the cached copy" in out.stderr and "is repaired" not in out.stderr, out.stderr
    size = (mini["mirror"] / "frame-000000.depth.png").stat().st_size
    assert f"downloading 1 file ({size / 1e3:.1f} kB)" in out.stderr, out.stderr
    assert _same_files(mini["final"], mini["mirror"])
