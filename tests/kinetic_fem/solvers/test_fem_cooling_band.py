"""The faster near-elastic defaults of the FEM cooling state (issue 16, seventh round).

Reference values: ``benchmarks/archive/accuracy_fem_cooling_speed.py``,
``fem_cooling_band_speed.md``
and the convergence study of ``benchmarks/results/fem_cooling.md`` (P2 at 0.035 hump widths,
Gauss degree 9)."""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem import cooling as fc
from kinetic_fem.solvers.fem.cooling_band import (
    BAND_DECADES,
    BAND_EFOLDS,
    BAND_EPS,
    BAND_GROWTH,
    BAND_RESOLUTION,
    band_state,
    band_vertices,
    in_band,
)
from kinetic_fem.solvers.fem.cooling_mesh import log_chain
from kinetic_fem.solvers.fem.cooling_newton import CLOSE_DAMPING


def test_band_default_is_p3_on_the_graded_band_mesh():
    """alpha = 0.95: P3 on band_vertices (0.12 hump widths, graded tail, 40 decades).

    Reference: P3 at 0.05 hump widths (2593 dofs, Gauss degree 9), zeta/eps =
    1.0023372652626432, a2 = -0.4572880278635882; the default measured 6.4e-15 and
    2.4e-14 from it, ln f 5.9e-7 where f > 1e-30 (613 dofs; the former band default on
    the moderate mesh, 1219 dofs: 1.9e-14, 6.3e-14, 3.6e-6)
    (benchmarks/archive/results/fem_cooling_band_speed.md).  Tolerances: ten times the former
    default's errors."""
    dist = kf.solve_cooling(0.95)
    extra = dist.info.extra
    assert dist.info.converged and extra["order"] == 3
    assert extra["n_dofs"] < 700 and extra["cutoff"] < 8.0
    assert extra["zeta"] / 0.05 == pytest.approx(1.0023372652626432, rel=2e-13)
    assert dist.a2 == pytest.approx(-0.4572880278635882, abs=6e-13)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-11)


def test_band_vertices_grade_along_the_tail():
    eps, w = 0.05, 0.05 ** (1.0 / 3.0)
    v = band_vertices(eps, lambda c: -0.5 * c**2)
    h = np.diff(v[v >= 0.0])
    c = v[v >= 0.0][:-1]
    assert np.allclose(h[c < 1.0 + 2.0 * w], BAND_RESOLUTION * w)
    linear = BAND_RESOLUTION * w * (1.0 + BAND_GROWTH * np.maximum(c - 1.0 - 2.0 * w, 0) / w)
    assert np.all(h <= linear * (1 + 1e-9)) and h.max() > 2.0 * h.min()
    # at most BAND_EFOLDS e-folds of the start per grown element (slope c)
    grown = h > BAND_RESOLUTION * w * (1 + 1e-9)
    assert grown.any() and np.all((h * c)[grown] <= BAND_EFOLDS * 1.05)
    # cut off where the start has fallen BAND_DECADES decades
    assert 0.5 * v[-2] ** 2 < BAND_DECADES * np.log(10.0) <= 0.5 * v[-1] ** 2
    with pytest.raises(ValueError, match="eps"):
        band_vertices(1.0, lambda c: -c)


def test_band_reaches_its_lower_end():
    """eps = BAND_EPS (0.035): measured 3.1e-15 in zeta, 2.0e-14 in a2 from P3 at 0.1 hump
    widths (the near-elastic default there: 3.2e-13, 2.2e-12)."""
    dist = kf.solve_cooling(1.0 - BAND_EPS)
    assert dist.info.converged and dist.info.extra["order"] == 3
    assert dist.info.extra["n_dofs"] < 700


def test_band_limits():
    assert in_band(BAND_EPS, fc.HUMP_EPS) and in_band(0.099, fc.HUMP_EPS)
    assert not in_band(0.1, fc.HUMP_EPS) and not in_band(0.9 * BAND_EPS, fc.HUMP_EPS)
    assert 0.0 < CLOSE_DAMPING < 1.0


def test_band_state_falls_back_when_it_fails(monkeypatch):
    """A failed band solve returns None and the default takes the continuation."""
    from types import SimpleNamespace

    from kinetic_fem.solvers.fem import cooling_band as fem_cooling_band

    failed = SimpleNamespace(info=SimpleNamespace(converged=False, message="no"),
                             u=np.zeros(3))
    monkeypatch.setattr(fem_cooling_band, "continued_state", lambda *a, **k: failed)
    problem = CoolingProblem.from_parameters(0.95)
    assert band_state(problem, fc.hump_start(2, None), fc.HUMP_EPS) is None


def test_p3_hump_default_at_eps_1e2():
    """alpha = 0.99: P3 at 0.2 hump widths (degree 9) refined from the P2 link state.

    Reference P2 at 0.035 hump widths: zeta/eps = 1.000518539452112, a2 =
    -0.595104102446; the default measured 8.4e-13 and 2.6e-11 from it (the former P2
    default at 0.07: 1.5e-11, 5.3e-10), ln f 1.7e-6 (7.6e-6)."""
    dist = kf.solve_cooling(0.99)
    extra = dist.info.extra
    assert dist.info.converged and extra["order"] == 3
    assert extra["zeta"] / 0.01 == pytest.approx(1.000518539452112, rel=5e-12)
    assert dist.a2 == pytest.approx(-0.595104102446, abs=1e-10)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-11)


def test_log_chain():
    chain = log_chain(1e-3, 0.1, 8.0)
    assert chain[-1] == 1e-3 and len(chain) == 3
    ratios = np.array([0.1, *chain[:-1]]) / np.array(chain)
    assert np.allclose(ratios, ratios[0]) and ratios.max() <= 8.0
    assert log_chain(0.05, 0.1, 8.0) == [0.05]


def test_band_from_a_far_warm_start():
    """initial = the state at eps = 1e-3 (a ratio 50): a link chain of ratio <= 16 on the
    fast link meshes, then the band mesh; the cold state to round-off (measured 5.6e-16 in
    zeta, 2.6e-15 in a2; the former default fell back to the near-elastic path, 3.4e-13
    off)."""
    cold = kf.solve_cooling(0.95)
    warm = kf.solve_cooling(0.95, initial=kf.solve_cooling(0.999))
    assert warm.info.extra["n_dofs"] == cold.info.extra["n_dofs"]
    assert warm.info.extra["zeta"] == pytest.approx(cold.info.extra["zeta"], rel=1e-13)
    assert warm.a2 == pytest.approx(cold.a2, abs=1e-13)
