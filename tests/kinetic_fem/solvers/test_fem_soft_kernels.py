"""FEM heated states of the soft kernels near elastic collisions with default options.

The defaults for gamma < 1 under white noise (:func:`fem_defaults.gain_margin`, the
cut-off of the gain-delayed tail, and :attr:`ScaledModel.continues_near_elastic`, the
Gaussian start instead of the continuation from ten times the inelasticity) used to fail
for the Maxwell model at alpha >= 0.88 (a spurious discrete state after the widening of
a truncated interval, or a diverging Newton from the rescaled state) and for
gamma = 0.5 at alpha = 0.99.
"""

from __future__ import annotations

import pytest

import kinetic_fem as kf
from kinetic_fem.solvers import maxwell
from kinetic_fem.solvers.fem import defaults as fem_defaults


@pytest.mark.parametrize("alpha", [0.88, 0.9, 0.95, 0.99, 0.999])
def test_maxwell_white_noise_near_elastic_defaults_are_exact(alpha):
    """Measured against the exact moment hierarchy: |dT/T| <= 4e-13, |da2| <= 1.6e-8
    (alpha = 0.88 ... 0.999); the defaults' accuracy is T 1e-8, a2 1e-6."""
    dist = kf.solve_heated(alpha, kernel=0.0)
    exact = maxwell.steady_state(alpha)
    assert dist.temperature == pytest.approx(exact.temperature, rel=1e-8)
    assert dist.a2 == pytest.approx(exact.a2, abs=1e-6)


def test_gamma_half_white_noise_alpha_099_matches_sonine():
    """gamma = 0.5, alpha = 0.99: the Sonine Galerkin series converges (orders 24 to 40
    agree to 3e-15 in T, 1e-15 in a2: T = 51.4356738702, a2 = -0.0616853865506); FEM
    with default options is within 2.6e-10 (T) and 3.4e-9 (a2) of it."""
    dist = kf.solve_heated(0.99, kernel=0.5)
    assert dist.temperature == pytest.approx(51.43567387019245, rel=1e-8)
    assert dist.a2 == pytest.approx(-0.06168538655058611, abs=1e-6)


@pytest.mark.parametrize("alpha, expected", [(0.88, 21.0), (0.9, 20.0), (0.95, 16.6)])
def test_cutoff_covers_the_gain_delayed_maxwell_tail(alpha, expected):
    """The default cut-off lies beyond the measured c where f(c) = 1e-33 (the bare tail
    rule e^(-v) placed it at 19.0, 17.6 and 12.9)."""
    model = fem_defaults.scaled_model(kf.HeatedProblem.from_parameters(alpha, kernel=0.0))
    assert expected < fem_defaults.model_cutoff(model) < expected + 2.0


def test_gain_margin_is_zero_for_hard_kernels_and_the_bath():
    for gamma, friction in [(1.0, 0.0), (2.0, 0.0), (0.0, 1.0), (0.5, 1.0)]:
        problem = kf.HeatedProblem.from_parameters(0.9, kernel=gamma, friction=friction)
        assert fem_defaults.gain_margin(fem_defaults.scaled_model(problem)) == 0.0
    hard = fem_defaults.scaled_model(kf.HeatedProblem.from_parameters(0.99, kernel=2.0))
    soft = fem_defaults.scaled_model(kf.HeatedProblem.from_parameters(0.99, kernel=0.5))
    assert hard.continues_near_elastic and not soft.continues_near_elastic
