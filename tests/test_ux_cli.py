"""A new user's pass over the CLI: bad input is one line on stderr and exit 2, summaries and
tables name things instead of printing internal keys or ids (each test runs the real CLI in a
subprocess with its own SG3D_HOME)."""
from __future__ import annotations

from pathlib import Path

import pytest

from tests.test_store_cli import one_error_line, sg3d

KITCHEN = Path(__file__).resolve().parents[2] / "shared" / "data" / "7scenes-redkitchen"


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
