"""`sg3d serve`'s default worker count from the machine's cores (`bounds.default_workers`)."""
from __future__ import annotations

from sg3d.app.bounds import default_workers


def test_the_store_keeps_two_cores_and_each_worker_takes_two_more():    # STORE_CORES, CORES_PER_WORKER
    assert default_workers(2) == 1
    assert default_workers(3) == 1
    assert default_workers(4) == 2
    assert default_workers(6) == 3


def test_at_most_four_workers_by_default():                             # MAX_DEFAULT_WORKERS
    assert default_workers(8) == 4
    assert default_workers(64) == 4


def test_one_worker_when_the_cores_are_unknown():
    assert default_workers(None) == 1
    assert default_workers(1) == 1
