"""The one mesher: vertices marched by a size rule (kinetic_fem.operators.mesher)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinetic_fem.operators.mesher import log_drop_size, march


def test_log_drop_rule_spreads_the_drop_of_ln_f_evenly():
    """ln f = -c^2/2 marched with one e-fold per element (from a first element of 0.5):
    every element past the bulk drops ln f by one e-fold at its inner vertex (c h = 1),
    so the exact drop over it is c h + h^2/2 = 1 + h^2/2."""

    def log_f(c):
        return -0.5 * c**2

    verts = march(lambda c: log_drop_size(c, 1.0, largest=0.5), 12.0)
    half = verts[verts >= 0.0]
    assert verts[0] == -verts[-1] and np.all(np.diff(verts) > 0) and 0.0 in verts
    assert half[-1] >= 12.0 and half[-2] < 12.0
    h = np.diff(half)
    inner = half[:-1]
    tail = inner > 2.0
    np.testing.assert_allclose(h[tail] * inner[tail], 1.0, rtol=1e-14)
    drop = log_f(half[:-1]) - log_f(half[1:])
    np.testing.assert_allclose(drop[tail], 1.0 + 0.5 * h[tail] ** 2, rtol=1e-12)


def test_snap_ends_at_the_cutoff():
    verts = march(lambda c: 0.3, 1.0, end="snap")
    assert verts[-1] == 1.0 and np.all(np.diff(verts) > 0)
    assert math.isclose(verts[-1] - verts[-2], 0.1 + 0.3)  # 0.9 -> 1.2 dropped


def test_stop_test_and_bad_input():
    verts = march(lambda c: 1.0, lambda c: c >= 3.0)
    np.testing.assert_array_equal(verts, np.arange(-3.0, 4.0))
    with pytest.raises(ValueError, match="end"):
        march(lambda c: 1.0, 3.0, end="stretch")
    with pytest.raises(ValueError, match="cut-off"):
        march(lambda c: 1.0, lambda c: c >= 3.0, end="snap")
