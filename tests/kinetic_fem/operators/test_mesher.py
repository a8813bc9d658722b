"""The one mesher: vertices marched by a size rule (kinetic_fem.operators.mesher)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinetic_fem.operators.mesher import (
    LogDropRule,
    ScaleGrading,
    log_drop_size,
    log_drop_vertices,
    march,
)


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


def test_log_drop_vertices_from_a_state_bound_the_drop_and_the_sizes():
    """ln f = -c^2/2 with at most 1.5 e-folds per element in [0.1, 0.6] after a uniform
    bulk to 1: the bulk is uniform, every element within the bounds, each drops ln f by
    at most 1.5 + h^2/2 (slope read at its inner vertex), and the mesh ends at the first
    vertex past the 20-decade point c = sqrt(40 ln 10) = 9.6."""
    rule = LogDropRule(efolds=1.5, smallest=0.1, largest=0.6, bulk=1.0, decades=20.0)
    verts = log_drop_vertices(lambda c: -0.5 * c**2, rule)
    half = verts[verts >= 0.0]
    h = np.diff(half)
    assert verts[0] == -verts[-1] and np.all(h > 0.0)
    np.testing.assert_allclose(h[half[:-1] < 1.0 - 1e-9], 0.1, rtol=1e-12)
    assert h.min() >= 0.1 - 1e-12 and h.max() <= 0.6 + 1e-12
    drop = 0.5 * (half[1:] ** 2 - half[:-1] ** 2)
    assert np.all(drop <= 1.5 + 0.5 * h**2 + 1e-9)  # the slope of a quadratic: exact
    free = (h > 0.1 + 1e-12) & (h < 0.6 - 1e-12) & (half[:-1] >= 1.0)  # neither bound
    assert free.sum() > 5
    np.testing.assert_allclose(drop[free], 1.5 + 0.5 * h[free] ** 2, rtol=1e-9)
    cut = math.sqrt(40.0 * math.log(10.0))
    assert half[-2] < cut <= half[-1] + 1e-3


def test_scale_grading_sizes_follow_the_model_scales():
    """h(c) = h0 max(1, c/c_b)^kappa: uniform in the bulk, grown as c^kappa in the tail;
    the marched mesh ends exactly at c_max; kappa = 0 stretched is uniform."""
    g = ScaleGrading(0.1, 2.0 / 3.0, bulk=3.0)
    marched = g.marched(20.0)
    half = marched[marched >= 0.0]
    h = np.diff(half)
    assert half[-1] == 20.0
    np.testing.assert_allclose(h[half[1:] <= 3.0], 0.1, rtol=1e-12)
    inner = half[:-2]  # all but the snapped last element
    np.testing.assert_allclose(h[:-1], [g.size(c) for c in inner], rtol=1e-12)
    stretched = g.stretched(20.0)
    assert stretched[-1] == 20.0 and np.all(np.diff(stretched) > 0)
    assert abs(stretched.size - marched.size) <= 2  # the same density, another placement
    uniform = ScaleGrading(0.5, 0.0).stretched(10.0)
    np.testing.assert_allclose(np.diff(uniform), 0.5, rtol=1e-12)
