"""The tail closure of the Maxwell model's cooling state: moments, quadrature, gain kernel."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from kinetic_fem.operators import maxwell_tail
from kinetic_fem.solvers.fem.heated import FEMDiscretisation


def test_tail_shape_is_the_expansion_of_the_closed_form():
    """g(c) = c^-4 (1 - 2/c^2 + 3/c^4): the closed form's series to c^-8 (the
    coefficients follow from the Fourier balance, module notes)."""
    c = np.array([50.0, 200.0, 1e4])
    exact = 1.0 / (1.0 + c**2) ** 2
    assert np.all(np.abs(maxwell_tail.tail_shape(c) / exact - 1.0) < 5.0 / c**6 + 1e-15)


@pytest.mark.parametrize("cutoff", [30.0, 200.0])
def test_tail_moments_and_quadrature(cutoff):
    g = maxwell_tail.tail_shape
    m, e = maxwell_tail.tail_moments(cutoff)
    assert m == pytest.approx(quad(lambda c: g(c), cutoff, np.inf, epsabs=0, epsrel=1e-13)[0],
                              rel=1e-11)
    assert e == pytest.approx(quad(lambda c: c * c * g(c), cutoff, np.inf, epsabs=0,
                                   epsrel=1e-13)[0], rel=1e-11)
    c, w = maxwell_tail.tail_quadrature(cutoff)
    assert np.all(c > cutoff) and np.all(np.diff(c) > 0)
    assert w @ g(c) == pytest.approx(m, rel=1e-13)
    assert w @ (c * c * g(c)) == pytest.approx(e, rel=1e-13)


@pytest.mark.parametrize("order", [2, 3])
@pytest.mark.parametrize("alpha", [0.0, 0.6, 0.99])
def test_gain_matrix_against_adaptive_quadrature(order, alpha):
    """K[i, q] = int_{|y|>V} g(|y|) [phi_i(a x + b y) + phi_i(b x + a y)] dy."""
    cutoff = 6.0
    verts = np.concatenate([np.linspace(0.0, 2.0, 5), np.geomspace(2.0, cutoff, 6)[1:]])
    verts = np.concatenate([-verts[:0:-1], verts])
    disc = FEMDiscretisation(alpha, verts, order, 2 * order + 1, gamma=0.0)
    mesh_v, dofs = disc.mesh_arrays
    xq = disc.points[0]
    k = maxwell_tail.tail_gain_matrix(mesh_v, dofs, order, xq, alpha, cutoff)
    a, b = 0.5 * (1.0 - alpha), 0.5 * (1.0 + alpha)
    rng = np.random.default_rng(3)
    for i, q in zip(rng.integers(0, k.shape[0], 6), rng.integers(0, xq.size, 6), strict=True):
        coef = np.zeros(k.shape[0])
        coef[i] = 1.0

        def phi(z, coef=coef):
            if abs(z) >= cutoff:
                return 0.0
            return float(np.log(disc.evaluate(coef, np.array([z]))[0]))

        x = xq[q]
        total = 0.0
        for s, c0 in ((b, a * x), (a, b * x)):
            for sign in (1.0, -1.0):
                # y = sign * w, z = c0 + s * y inside the mesh
                w_hi = (cutoff + sign * (-c0)) / s if sign > 0 else (c0 + cutoff) / s
                if w_hi <= cutoff:
                    continue
                brk = [w for w in np.abs((verts - c0) / s) if cutoff < w < w_hi]
                total += quad(lambda w, s=s, c0=c0, sign=sign: maxwell_tail.tail_shape(w)
                              * phi(c0 + sign * s * w), cutoff, w_hi, points=brk or None,
                              limit=400, epsabs=1e-15, epsrel=1e-11)[0]
        assert k[i, q] == pytest.approx(total, rel=1e-8, abs=1e-14)
