"""A bag's timed transforms (`sg3d.ingest.readers.bag.PoseSeries`), without a bag file."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from sg3d.ingest.readers.bag import PoseSeries

SECOND = 1_000_000_000


def _series(gap_s: float) -> PoseSeries:
    """Two samples `gap_s` apart, the camera moving 1 m along x."""
    s = PoseSeries()
    still = SimpleNamespace(x=0.0, y=0.0, z=0.0, w=1.0)
    s.add(0, SimpleNamespace(x=0.0, y=0.0, z=0.0), still)
    s.add(int(gap_s * SECOND), SimpleNamespace(x=1.0, y=0.0, z=0.0), still)
    return s


def test_poses_up_to_half_a_second_apart_are_interpolated():          # MAX_INTERPOLATION_GAP
    tol = int(0.02 * SECOND)
    inside = _series(0.49).at(int(0.245 * SECOND), tol)
    assert inside is not None and inside[0, 3] == pytest.approx(0.5)
    assert _series(0.51).at(int(0.255 * SECOND), tol) is None          # and none is near enough
    assert np.allclose(_series(0.51).at(int(0.01 * SECOND), tol)[:3, 3], 0.0)
