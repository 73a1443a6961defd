"""Shared fixtures: the real data beside the repo, and one real embedded store per session."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared"))
KITCHEN = SHARED / "data" / "7scenes-redkitchen"


def need_shared(path: Path, what: str) -> Path:
    """`path` under ../shared, or a skip naming it (a failure in CI, which always has ../shared)."""
    if not path.exists():
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(f"{what} not found at {path} in CI")
        pytest.skip(f"{what} not found at {path} (set SG3D_SHARED to the shared data folder)")
    return path


@pytest.fixture(scope="session")
def kitchen_dir() -> Path:
    """The real 7-Scenes red kitchen; skips (with the reason) where ../shared is absent."""
    if not (KITCHEN / "camera-intrinsics.txt").exists():
        if os.environ.get("CI", "").lower() == "true":   # CI always has ../shared: a skip would hide a failure
            pytest.fail("real kitchen data not found at ../shared/data/7scenes-redkitchen in CI")
        pytest.skip("real kitchen data not found at ../shared/data/7scenes-redkitchen (set SG3D_SHARED)")
    return KITCHEN


@pytest.fixture(scope="session")
def embedded_home(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("sg3d-home")


@pytest.fixture(scope="session")
def store_session(embedded_home):
    """One real embedded ArcadeDB server for the whole test session, reached over Bolt."""
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.store import Store

    server = EmbeddedServer(embedded_home)
    info = server.ensure_running()
    store = Store(info.uri, (info.user, info.password), info.database)
    store.ensure_schema()
    yield store
    store.close()
    server.stop()


@pytest.fixture
def store(store_session):
    """The session's store, emptied before each test."""
    store_session.wipe()
    store_session.ensure_schema()
    return store_session


@pytest.fixture
def house(store):
    """The hand-made two-room house `ask` is tested on (tests/scenes.py): local id -> global id."""
    from tests.scenes import build_house

    return build_house(store)


@pytest.fixture(scope="module")
def served(store_session, embedded_home):
    """`sg3d serve`'s app on a free loopback port over the session's store: (url, token)."""
    from sg3d.server.auth import ensure_token
    from sg3d.settings import Settings
    from tests.serve_helpers import running_server

    token = ensure_token(embedded_home)
    with running_server(Settings(home=embedded_home), token) as url:
        yield url, token


@pytest.fixture
def kitchen_client(served, store):
    """An authenticated httpx client of the served app, with the sample kitchen ingested."""
    import httpx

    from tests.serve_helpers import kitchen_body

    url, token = served
    with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=60) as c:
        assert c.post("/ingest", json=kitchen_body()).status_code == 200
        yield c


@pytest.fixture
def own_store(tmp_path):
    """A store of its own (damaged on purpose by the trust tests) holding the sample kitchen
    ingest: (home, server)."""
    from sg3d.app.ingest import IngestRequest, ingest_graph
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.settings import Settings
    from sg3d.testing import kitchen_body

    home = tmp_path / "home"
    store = Settings(home=home).store()
    store.ensure_schema()
    ingest_graph(store, IngestRequest.model_validate(kitchen_body()))
    store.close()
    server = EmbeddedServer(home)
    yield home, server
    server.stop()


# Each folder of tests/ is a lane, and its tests carry its marker (`pytest -m unit`, `-m "not quality"`):
# unit (no store, no process, no data), e2e (a real store, server, CLI or data), quality (a room's
# figures against its ground truth), repo (the repository's own files: code shape, docs, README).
LANES = ("unit", "e2e", "quality", "repo")


def pytest_collection_modifyitems(config, items):
    tests = Path(__file__).resolve().parent
    for item in items:
        parts = Path(item.path).resolve().relative_to(tests).parts
        if parts and parts[0] in LANES:
            item.add_marker(parts[0])
