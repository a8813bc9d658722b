"""Tests of the near-elastic HCS meshes and the error indicator (operators.adaptive)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinetic_fem.operators.adaptive import (
    EDGE_EFOLDS,
    HUMP_DECADES,
    element_indicator,
    hump_vertices,
    refined_vertices,
)


@pytest.mark.parametrize("eps", [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6])
def test_hump_mesh_resolves_the_hump_width(eps):
    """Elements of resolution * eps^(1/3) over the hump core, symmetric, vertex at 0,
    cut-off where the outer edge exp(-|y|^3/3) has fallen HUMP_DECADES decades."""
    w = eps ** (1 / 3)
    v = hump_vertices(eps, eps, resolution=0.1)
    assert np.all(np.diff(v) > 0) and 0.0 in v
    assert np.allclose(v, -v[::-1], rtol=0, atol=1e-14)
    h = np.diff(v)
    mid = 0.5 * (v[1:] + v[:-1])
    core = np.abs(np.abs(mid) - 1.0) < 2 * w
    assert h[core].max() <= 0.1 * w * (1 + 1e-9)
    outer = (3 * HUMP_DECADES * math.log(10)) ** (1 / 3)
    assert v[-1] >= 1 + w * outer - 1e-12
    assert v.size < 3000  # geometric grading away from the humps


@pytest.mark.parametrize("eps", [1e-2, 1e-4, 1e-6])
def test_outer_edge_elements_fall_at_most_efolds(eps):
    """Beyond the humps (c > 1) each element spans at most EDGE_EFOLDS e-folds of
    psi's outer edge e^(-y^3/3) (coarser elements make the Galerkin drift unstable), and
    the mesh ends at the first vertex past the cut-off (no stretched last element)."""
    w = eps ** (1 / 3)
    v = hump_vertices(eps, eps, resolution=0.07)
    edge = v[v > 1.0]
    y = (edge - 1.0) / w
    falls = np.diff(y**3 / 3)
    assert falls.max() <= 1.25 * EDGE_EFOLDS  # y^2 h at the left vertex is the rule
    h = np.diff(v)
    assert h[-1] <= h[-2] * (1 + 1e-9)  # the last element is not stretched
    outer = (3 * HUMP_DECADES * math.log(10)) ** (1 / 3)
    assert 0.0 <= v[-1] - (1 + w * outer) <= h[-1]


def test_edge_slope_sets_the_outer_elements():
    """An explicit edge slope (a starting guess's |d ln f/dc|) replaces psi's."""
    eps, w = 1e-3, 0.1
    v = hump_vertices(eps, eps, resolution=0.07, edge_slope=lambda c: 50.0)
    h = np.diff(v)[v[:-1] >= 1.0]
    assert np.allclose(h[:-1], min(0.07 * w, EDGE_EFOLDS / 50.0))
    with pytest.raises(ValueError, match="efolds"):
        hump_vertices(eps, eps, efolds=0.0)


def test_indicator_tracks_the_interpolation_error():
    """On u = ln f of a hump profile the indicator estimates the max P2 interpolation
    error per element within a factor of 2 where the error is not negligible."""
    x = np.linspace(-2.0, 2.0, 81)
    u = lambda s: -(s**3) / 3 + np.sin(3 * s)  # noqa: E731
    m = 0.5 * (x[1:] + x[:-1])
    eta = element_indicator(x, u(x), u(m))
    true = np.empty_like(eta)
    for k, (a, b) in enumerate(zip(x[:-1], x[1:], strict=True)):
        t = np.linspace(a, b, 201)
        mm = 0.5 * (a + b)
        interp = (u(a) * (t - mm) * (t - b) / ((a - mm) * (a - b))
                  + u(mm) * (t - a) * (t - b) / ((mm - a) * (mm - b))
                  + u(b) * (t - a) * (t - mm) / ((b - a) * (b - mm)))
        true[k] = np.abs(u(t) - interp).max()
    big = true > 1e-2 * true.max()
    ratio = eta[big] / true[big]
    assert 0.5 < ratio.min() and ratio.max() < 2.0


def test_refinement_reduces_the_indicator():
    x = np.linspace(0.0, 1.0, 11)
    u = lambda s: np.exp(4 * s)  # noqa: E731
    eta = element_indicator(x, u(x), u(0.5 * (x[1:] + x[:-1])))
    target = eta.max() / 30
    y = refined_vertices(x, eta, target)
    eta2 = element_indicator(y, u(y), u(0.5 * (y[1:] + y[:-1])))
    assert set(x).issubset(set(y))
    assert eta2.max() < 1.5 * target


def test_bad_input():
    with pytest.raises(ValueError, match="eps"):
        hump_vertices(0.0, 0.1)
    with pytest.raises(ValueError, match="eps"):
        hump_vertices(1.5, 0.1)
    with pytest.raises(ValueError, match="resolution"):
        hump_vertices(0.1, 0.1, resolution=-1.0)
    with pytest.raises(ValueError, match="increasing"):
        element_indicator(np.array([0.0, 2.0, 1.0]), np.zeros(3), np.zeros(2))
    with pytest.raises(ValueError, match="shape"):
        refined_vertices(np.array([0.0, 1.0, 2.0]), np.ones(3), 1e-3)
