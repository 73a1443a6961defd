"""The fast lane's guard refuses processes, connections and the shared data, and lets the rest be."""
from __future__ import annotations

import socket
import subprocess
import sys

import pytest

from tests.unit.lane_guard import SHARED, LaneError


def test_starting_a_process_is_refused():
    with pytest.raises(LaneError, match="started a process"):
        subprocess.run([sys.executable, "-c", "pass"], check=False)


def test_connecting_a_socket_is_refused():
    with socket.socket() as s, pytest.raises(LaneError, match="opened a connection"):
        s.connect(("127.0.0.1", 9))


def test_reading_the_shared_data_is_refused():
    with pytest.raises(LaneError, match="read the shared data"):
        with open(SHARED / "data" / "anything.txt", "rb"):
            pass


def test_files_the_test_writes_itself_are_fine(tmp_path):
    path = tmp_path / "made-here.txt"
    path.write_text("hand-made\n")
    assert path.read_text() == "hand-made\n"
