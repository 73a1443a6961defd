"""Shared by the benchmarks: a throw-away embedded store and a generator of synthetic objects."""
from __future__ import annotations

import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from sg3d.core.model import HIST_SIZE, ObjectObservation

LABELS = ["cup", "bowl", "chair", "dining table", "tv", "bottle", "sink", "couch", "book", "vase"]


CYPHER = Path(__file__).with_name("cypher")


def load_cypher(name: str) -> str:
    """A benchmark's own statement from benchmarks/cypher/NAME.cypher, its comment lines left out
    (the probes it writes and the statements it sends as a user would, never product templates)."""
    text = (CYPHER / f"{name}.cypher").read_text()
    return "\n".join(ln for ln in text.splitlines() if not ln.lstrip().startswith("//")).strip()


@contextmanager
def scratch_store():
    """A fresh embedded store in a temporary home, stopped afterwards."""
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.store import Store

    with tempfile.TemporaryDirectory(prefix="sg3d-bench-") as home:
        server = EmbeddedServer(Path(home))
        info = server.start()
        store = Store(info.uri, (info.user, info.password), info.database)
        store.ensure_schema()
        try:
            yield store
        finally:
            store.close()
            server.stop()


def synthetic_object(rng: np.random.Generator, i: int, extent=(20.0, 3.0, 20.0)) -> ObjectObservation:
    hist = np.zeros(HIST_SIZE)
    hist[rng.integers(0, HIST_SIZE, 6)] = rng.integers(10, 200, 6)
    return ObjectObservation(
        local_id=f"l{i}", labels=[LABELS[i % len(LABELS)]], scores=[float(rng.uniform(0.3, 1))],
        mean=tuple(rng.uniform(0, 1, 3) * extent), var=(0.01, 0.01, 0.01), n_points=100,
        size=(0.2, 0.2, 0.2), hist=hist, colour="white", thumbnail=b"\xff" * 4000,
        first_frame=i, last_frame=i)


class CountingStore:
    """A store that counts the queries sent through it (each one Bolt round trip): a figure of
    a question's cost that does not depend on the machine's load."""

    def __init__(self, store):
        self._store, self.sent = store, []

    def read(self, name, **params):
        self.sent.append(name)
        return self._store.read(name, **params)

    def session(self, **kw):
        self.sent.append("session")
        return self._store.session(**kw)

    def __getattr__(self, name):
        return getattr(self._store, name)
