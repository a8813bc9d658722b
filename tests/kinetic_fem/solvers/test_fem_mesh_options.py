"""The mesh options of the FEM engine (MeshOptions): element order, quadrature degree and
tail grading, each checked on the heated hard-rod state at alpha = 0.5 (issue 26).

Figures measured (cut-off 20, reference P3 at spacing 0.05): the errors of T and a2 fall
as h^4 with P2 (observed orders 3.99-4.01 over spacings 0.8/0.4/0.2) and as h^6 with P3
(5.97-6.00): the moments superconverge at twice the degree.  The default Gauss degree
2 order + 1 (5 for P2) moves T and a2 at spacing 0.4 by 9e-9 and 2.4e-8 from degree 9,
0.5 % of their discretisation errors (1.6e-6, 7.1e-6); degrees 9 and 11 differ by 1e-11.
"""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.solvers.fem.cooling import solve_fem_cooling
from kinetic_fem.solvers.fem.heated import steady_state
from kinetic_fem.solvers.fem.options import MeshOptions

ALPHA = 0.5
CUTOFF = 20.0


def _moments(**mesh):
    state = steady_state(ALPHA, cutoff=CUTOFF, **mesh)
    dist = state.disc.distribution(state.u)
    return np.array([dist.temperature, dist.a2]), state


@pytest.fixture(scope="module")
def reference():
    return _moments(order=3, spacing=0.05)[0]


def test_p3_converges_at_a_higher_observed_order_than_p2(reference):
    rates = {}
    for order in (2, 3):
        coarse, fine = (np.abs(_moments(order=order, spacing=h)[0] - reference)
                        for h in (0.4, 0.2))
        rates[order] = np.log2(coarse / fine)
    # measured 4.00 (T), 4.00 (a2) and 6.00, 6.00
    assert np.all(np.abs(rates[2] - 4.0) < 0.3)
    assert np.all(np.abs(rates[3] - 6.0) < 0.5)


def test_quadrature_degree_changes_results_at_the_quadrature_error_level(reference):
    default, _ = _moments(order=2, spacing=0.4)
    d9, _ = _moments(order=2, spacing=0.4, intorder=9)
    d11, _ = _moments(order=2, spacing=0.4, intorder=11)
    discretisation = np.abs(default - reference)
    quadrature = np.abs(default - d9)
    assert np.all(quadrature > 0.0)                          # the option is used
    assert np.all(quadrature < 0.02 * discretisation)       # measured 0.5 %
    assert np.all(np.abs(d9 - d11) < 1e-3 * quadrature)     # degree 9 converged


def test_tail_grading_option(reference):
    uniform, s_uniform = _moments(order=2, spacing=0.4)
    zero, s_zero = _moments(mesh=MeshOptions(order=2, spacing=0.4, grading=0.0))
    np.testing.assert_allclose(s_zero.disc.vertices, s_uniform.disc.vertices, rtol=0,
                               atol=1e-12)
    graded, s_graded = _moments(order=2, spacing=0.4, grading=0.6)
    # the tail's elements grow: fewer vertices (59 against 101), the same accuracy in
    # the moments (measured errors 0.97 of the uniform mesh's)
    assert s_graded.disc.vertices.size < 0.7 * s_uniform.disc.vertices.size
    assert np.all(np.abs(graded - reference) < 1.1 * np.abs(uniform - reference))
    with pytest.raises(ValueError, match="grading must be a finite number >= 0"):
        steady_state(ALPHA, grading=-1.0)
    with pytest.raises(ValueError, match="grading=0.5: the cooling state's meshes"):
        solve_fem_cooling(None, grading=0.5)  # refused before the problem is read
