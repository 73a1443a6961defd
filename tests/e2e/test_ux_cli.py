"""A new user's pass over the CLI: bad input is one line on stderr and exit 2, summaries and
tables name things instead of printing internal keys or ids (each test runs the real CLI in a
subprocess with its own SG3D_HOME)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli_helpers import one_error_line, sg3d

KITCHEN = Path(__file__).resolve().parents[3] / "shared" / "data" / "7scenes-redkitchen"


@pytest.mark.parametrize("args", [
    ["build", "SEQ", "--room", "r", "--method", "foo"],
    ["build", "SEQ", "--room", "r", "--stop", "abc"],
    ["build", "SEQ"],
    ["frames", "SEQ", "--limit", "0"],
    ["serve", "--port", "abc"],
    ["export", "--format", "xml"],
    ["no-such-command"],
])
def test_a_usage_error_is_one_line_naming_the_help(tmp_path, args):
    args = [str(tmp_path) if a == "SEQ" else a for a in args]
    line = one_error_line(sg3d(tmp_path / "home", *args))
    assert "--help" in line


@pytest.fixture(scope="module")
def walk_builds(tmp_path_factory):
    """A 12-frame synthetic walk built twice into one home: as text and as --json."""
    from tests.sequences import write_walk

    root = tmp_path_factory.mktemp("walk")
    seq = write_walk(root / "walk", blurry=())
    home = root / "home"
    try:
        text = sg3d(home, "build", str(seq), "--room", "hall", timeout=300)
        js = sg3d(home, "build", str(seq), "--room", "porch", "--json", timeout=300)
        assert text.returncode == 0 and js.returncode == 0, (text.stderr, js.stderr)
        yield text, json.loads(js.stdout)
    finally:
        sg3d(home, "db", "stop")


def test_build_summary_says_in_words_where_the_room_is_placed(walk_builds):
    text, _ = walk_builds
    row = next(line for line in text.stdout.splitlines() if "in building" in line)
    assert "reference room of the building" in row
    assert "how " not in row          # the placement dict's keys are not for the user


def test_an_interrupted_summary_says_so_and_how_far_detection_got(walk_builds):
    from rich.console import Console

    from sg3d.commands.build import _summary_table

    _, summary = walk_builds
    f = summary["frames"]
    chosen = f["keyframes"] + f["anchors"] + f["coverage"]
    summary = {**summary, "interrupted": True, "placement": None,
               "frames": {**f, "detected": chosen - 2, "read": f["read"] - 1}}
    console = Console(width=200, record=True)
    console.print(_summary_table(summary))
    out = console.export_text()
    assert "interrupted" in out.splitlines()[0]
    assert f"{chosen - 2} of {chosen} chosen frames" in out
    assert "detections in the finished chunks" in out   # the cut chunk's are not counted: not "0 detections"
    assert "input frames/s" not in out   # a speed over an interrupted run means nothing


def test_eval_tables_name_objects_not_ids(store, embedded_home, tmp_path):
    from tests.scenes import EVAL_BUILDING as BUILDING
    from tests.scenes import EVAL_GT as GT
    from tests.scenes import EVAL_ROOM as ROOM
    from tests.scenes import build_eval_room as build_room

    nodes = build_room(store)
    gt_file = tmp_path / "gt.json"
    gt_file.write_text(json.dumps(GT))
    out = sg3d(embedded_home, "eval", "--gt", str(gt_file), "--room", ROOM, "--building", BUILDING, "--no-vqa",
               COLUMNS="200")
    assert out.returncode == 0, out.stderr
    assert not any(node_id[:8] in out.stdout for node_id in nodes.values()), out.stdout
    rows: dict[str, str] = {}
    for line in out.stdout.splitlines():
        if line.count("│") > 3:
            kind = line.split("│")[1].strip()
            rows[kind] = rows.get(kind, "") + " ".join(line.split()) + "\n"
    assert any("black chair" in r and "H chair" in r for r in rows["match"].splitlines()), rows
    assert "red chair" in rows["duplicate"] and "tv" in rows["spurious"], rows


def test_serve_on_a_port_in_use_is_one_line_and_starts_nothing(tmp_path):
    import socket

    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        out = sg3d(tmp_path / "home", "serve", "--port", str(port), timeout=120)
    line = one_error_line(out)
    assert str(port) in line and "in use" in line
    assert not (tmp_path / "home" / "server.json").exists()   # the store was not started for nothing


def test_serve_on_an_unknown_host_is_one_line(tmp_path):
    line = one_error_line(sg3d(tmp_path / "home", "serve", "--host", "no-such-host.invalid", timeout=120))
    assert "no-such-host.invalid" in line


@pytest.mark.parametrize("args, words", [
    (["--format", "spark-dsg", "--out", "OUT.spark-dsg"], ".json"),
    (["--format", "spark-dsg", "--out", "OUT"], ".json"),
    (["--format", "graphml", "--thumbnails"], "--thumbnails"),
    (["--format", "3dssg", "--histograms"], "--histograms"),
])
def test_export_refuses_options_that_would_do_nothing_or_write_an_unreadable_file(tmp_path, args, words):
    out = sg3d(tmp_path / "home", "export", *[str(tmp_path / a) if a.startswith("OUT") else a for a in args])
    assert words in one_error_line(out)
    assert not list(tmp_path.glob("OUT*"))
    assert not (tmp_path / "home" / "server.json").exists()   # refused before the store starts


def _commands(cmd, path="sg3d"):
    import click

    yield path, cmd
    if isinstance(cmd, click.Group):          # through list/get: the sg3d group loads its commands lazily
        for name in cmd.list_commands(click.Context(cmd)):
            yield from _commands(cmd.get_command(click.Context(cmd), name), f"{path} {name}")


def test_every_option_of_every_command_says_what_it_does():
    import click

    from sg3d.cli import cli

    bare = [(path, p.opts[0]) for path, cmd in _commands(cli) for p in cmd.params
            if isinstance(p, click.Option) and not p.hidden and not (p.help or "").strip()]
    assert not bare, bare


@pytest.mark.parametrize("args, words", [
    (["--out", "MISSING/x.png"], "does not exist"),
    (["--viewpoint", "1,2"], "X,Y,Z"),
    (["--viewpoint", "1,2,z"], "X,Y,Z"),
])
def test_ask_refuses_a_bad_out_or_viewpoint_in_one_line_before_the_store_starts(tmp_path, args, words):
    args = [str(tmp_path / a) if a.startswith("MISSING") else a for a in args]
    out = sg3d(tmp_path / "home", "ask", "which cup is the biggest?", *args)
    assert words in one_error_line(out)
    assert not (tmp_path / "home" / "server.json").exists()


def test_a_build_that_read_no_frame_prints_no_speed(walk_builds):
    from rich.console import Console

    from sg3d.commands.build import _summary_table

    _, summary = walk_builds
    summary = {**summary, "input_frames_per_second": 0.0, "frames": {**summary["frames"], "read": 0}}
    console = Console(width=200, record=True)
    console.print(_summary_table(summary))
    assert "input frames/s" not in console.export_text()   # everything was merged already


def test_show_sequence_shows_progress_over_the_frames(store, embedded_home, tmp_path):
    from tests.scenes import EVAL_BUILDING as BUILDING
    from tests.scenes import EVAL_ROOM as ROOM
    from tests.scenes import build_eval_room as build_room
    from tests.sequences import write_walk

    build_room(store)
    seq = write_walk(tmp_path / "walk", n=6, blurry=())
    page = tmp_path / "view.html"
    out = sg3d(embedded_home, "show", "--building", BUILDING, "--room", ROOM, "--out", str(page),
               "--sequence", str(seq), "--frames", "6", COLUMNS="120")
    assert out.returncode == 0, out.stderr
    assert page.stat().st_size > 0
    assert "point cloud" in out.stderr and "6/6" in out.stderr, out.stderr


@pytest.mark.parametrize("args", [["shell", "--help"], ["mcp", "--help"], ["db", "status", "--help"],
                                  ["rooms", "link", "--help"], ["frames", "--help"], ["cypher", "--help"]])
def test_commands_load_on_demand_whatever_their_module_is_named(args):
    from click.testing import CliRunner

    from sg3d.cli import cli

    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 0, res.output
    assert res.output.startswith(f"Usage: cli {' '.join(args[:-1])}")


def test_an_unknown_command_is_one_line(tmp_path):
    out = sg3d(tmp_path / "home", "nosuch")
    assert "No such command 'nosuch'" in one_error_line(out)
