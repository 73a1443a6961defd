"""Pooling Gaussian position estimates: used when a track fuses its frames and when the store
updates a node with a new observation (paper Sec. V-C.2)."""
from __future__ import annotations

from typing import Any

import numpy as np


def combine_gaussians(mean_o: Any, var_o: Any, n_o: int, mean_c: Any, var_c: Any,
                      n_c: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Mean and variance of the union of both point sets, from their moments (per axis).

    Equivalent to recomputing over all points: E[x²] of each set is var + mean².
    """
    n = n_o + n_c
    if n == 0:
        return np.asarray(mean_o, float), np.asarray(var_o, float), 0
    mean_o, var_o, mean_c, var_c = (np.asarray(a, dtype=float) for a in (mean_o, var_o, mean_c, var_c))
    mean = (n_o * mean_o + n_c * mean_c) / n
    second = (n_o * (var_o + mean_o ** 2) + n_c * (var_c + mean_c ** 2)) / n
    return mean, np.maximum(second - mean ** 2, 0.0), n
