"""The fast lane: tests here run without a store, a subprocess or the data beside the repo.

While one of them runs (set-up, call and tear-down), an audit hook turns starting a process,
connecting a socket (Bolt, HTTP) or opening a file under ../shared into a `LaneError`, and the
fixtures that hand out a store or real data fail with the reason. A test that needs any of them
belongs in tests/e2e (or tests/quality for a room's figures).
"""
from __future__ import annotations

from pathlib import Path

import pytest

from tests.unit import lane_guard

lane_guard.install()


UNIT = Path(__file__).resolve().parent


@pytest.hookimpl(wrapper=True)
def pytest_runtest_protocol(item, nextitem):
    # pytest calls this hook for every item of the session, not only for those under this folder
    lane_guard.guard(UNIT in Path(item.path).resolve().parents)
    try:
        return (yield)
    finally:
        lane_guard.guard(False)


def _refused(what: str):
    pytest.fail(f"tests/unit runs without {what}: move this test out of tests/unit", pytrace=False)


@pytest.fixture(scope="session")
def embedded_home():
    _refused("a store home")


@pytest.fixture(scope="session")
def store_session():
    _refused("a store")


@pytest.fixture
def store():
    _refused("a store")


@pytest.fixture
def house():
    _refused("a store")


@pytest.fixture(scope="module")
def served():
    _refused("a server")


@pytest.fixture(scope="session")
def kitchen_dir():
    _refused("the real data")
