"""ABIR: Eq. 1-4 against values computed here independently (closed forms, plain NumPy)."""
from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from sg3d.ingest.select.abir import (
    ABIR,
    bias_corrected,
    blur_threshold,
    ema_update,
    variance_of_laplacian,
)

VARIANCES = [120.0, 135.0, 20.0, 150.0, 140.0, 15.0, 160.0, 130.0]


def _expected_thresholds(vs, alpha, gain, offset, paper_start=False):
    """Closed form of Eq. 2-3: S'_t is a normalised weighted sum, no recursion."""
    out = []
    for t in range(1, len(vs) + 1):
        weights = [(1 - alpha) * alpha ** (t - k) for k in range(1, t + 1)]
        if paper_start:
            weights[0] = alpha ** (t - 1)
        s = sum(w * v for w, v in zip(weights, vs[:t]))
        out.append(gain * math.log(1 + s / (1 - alpha ** t)) + offset)
    return out


@pytest.mark.parametrize("alpha,gain,offset", [(0.9, 30.0, 25.0), (0.9, 10.0, 25.0), (0.5, 12.0, 3.0)])
def test_threshold_follows_eq_2_to_4(alpha, gain, offset):
    abir = ABIR(alpha=alpha, gain=gain, offset=offset)
    decisions = [abir.update_variance(v) for v in VARIANCES]
    expected = _expected_thresholds(VARIANCES, alpha, gain, offset)
    assert [d.threshold for d in decisions] == pytest.approx(expected, rel=1e-12)
    assert [d.blurry for d in decisions] == [v < e for v, e in zip(VARIANCES, expected)]


def test_first_threshold_uses_the_first_variance_itself():
    d = ABIR(alpha=0.9, gain=30, offset=25).update_variance(100.0)
    assert d.threshold == pytest.approx(30 * math.log(101) + 25)


def test_paper_start_reproduces_printed_eq_2():
    abir = ABIR(alpha=0.9, gain=10, offset=25, paper_start=True)
    got = [abir.update_variance(v).threshold for v in VARIANCES]
    assert got == pytest.approx(_expected_thresholds(VARIANCES, 0.9, 10, 25, paper_start=True), rel=1e-12)
    paper = ABIR.paper()
    got = [paper.update_variance(v).threshold for v in VARIANCES]
    assert got == pytest.approx(_expected_thresholds(VARIANCES, 0.9, 30, 25, paper_start=True), rel=1e-12)


def test_equation_functions():
    assert ema_update(10.0, 20.0, 0.9) == pytest.approx(11.0)
    assert bias_corrected(2.0, 0.5, 1) == pytest.approx(4.0)
    assert bias_corrected(3.0, 0.5, 2) == pytest.approx(4.0)
    assert blur_threshold(math.e - 1, 10.0, 5.0) == pytest.approx(15.0)


def test_variance_of_laplacian_matches_eq_1():
    rng = np.random.default_rng(3)
    img = rng.integers(0, 256, size=(40, 50), dtype=np.uint8)
    p = np.pad(img.astype(np.float64), 1, mode="reflect")  # OpenCV's default border (reflect-101)
    lap = p[:-2, 1:-1] + p[2:, 1:-1] + p[1:-1, :-2] + p[1:-1, 2:] - 4 * p[1:-1, 1:-1]
    expected = np.mean(lap ** 2) - np.mean(lap) ** 2
    assert variance_of_laplacian(img) == pytest.approx(expected, rel=1e-6)
    assert variance_of_laplacian(cv2.cvtColor(img, cv2.COLOR_GRAY2BGR)) == pytest.approx(expected, rel=1e-6)


def test_blurred_frame_in_a_sharp_stream_is_rejected():
    rng = np.random.default_rng(0)
    texture = cv2.resize(rng.integers(0, 256, size=(60, 80), dtype=np.uint8), (320, 240),
                         interpolation=cv2.INTER_NEAREST)
    # low contrast puts V (~140) where real 640x480 indoor frames are
    base = (128 + (texture.astype(np.float64) - 128) * 0.1).astype(np.uint8)
    abir = ABIR()
    for k in range(10):
        assert not abir.update(np.roll(base, k, axis=1)).blurry
    motion = np.zeros((1, 15), np.float32)
    motion[:] = 1 / 15
    blurred = cv2.filter2D(base, -1, motion)
    d = abir.update(blurred)
    assert d.blurry and d.variance < d.threshold
    assert not abir.update(base).blurry


# --------------------------------------------------------------------------- the defaults, on both sides

def test_the_default_threshold_is_10_ln_1_plus_s_plus_25():  # DEFAULT_GAIN, DEFAULT_ALPHA, DEFAULT_OFFSET
    abir = ABIR()
    first = abir.update_variance(100.0)
    assert first.threshold == pytest.approx(10 * math.log(101) + 25)   # 71.15: V = 100 is sharp
    assert not first.blurry
    # S_2 = 0.9 * 10 + 0.1 * 60 = 15, S'_2 = 15 / 0.19: threshold 69.03, so V = 60 is blurry
    second = abir.update_variance(60.0)
    assert second.threshold == pytest.approx(10 * math.log(1 + 15 / 0.19) + 25)
    assert second.blurry
    # a first frame is judged against its own V: 75 clears 10 ln 76 + 25 = 68.3, 60 misses 66.1
    assert not ABIR().update_variance(75.0).blurry and ABIR().update_variance(60.0).blurry


def test_the_papers_gain_is_30():                                     # PAPER_GAIN
    # the printed Eq. 2 starts S_1 = V_1, so S'_1 = V_1 / (1 - 0.9) = 1000
    assert ABIR.paper().update_variance(100.0).threshold == pytest.approx(30 * math.log(1001) + 25)
