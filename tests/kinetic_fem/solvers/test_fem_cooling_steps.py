"""Speculative Jacobians and stopping on the step (fem_cooling_steps, issue 16)."""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.solvers.fem.cooling_steps import SpeculativeSystem, newton_on_step
from kinetic_fem.solvers.newton import newton


class Counted:
    """x_i^3 + x_i = b_i, counting residual and Jacobian evaluations."""

    def __init__(self) -> None:
        self.b = np.array([2.0, 10.0, 30.0])
        self.residuals = self.jacobians = 0

    def __call__(self, x, jacobian=True):
        self.residuals += 1
        self.jacobians += bool(jacobian)
        return x**3 + x - self.b, np.diag(3.0 * x**2 + 1.0) if jacobian else None


def test_speculative_system_same_iterates_one_call_per_step():
    plain, spec = Counted(), Counted()
    a = newton(plain, np.zeros(3), tol=1e-13, max_iter=30)
    b = newton(SpeculativeSystem(spec), np.zeros(3), tol=1e-13, max_iter=30)
    assert a.converged and b.iterations == a.iterations
    np.testing.assert_array_equal(a.x, b.x)
    assert spec.residuals < plain.residuals  # accepted trials: their Jacobian reused
    assert spec.residuals == spec.jacobians


def test_speculative_jacobian_is_handed_out_once():
    system = SpeculativeSystem(Counted())
    x = np.ones(3)
    r, j = system(x, False)
    assert j is None
    r2, j2 = system(x, True)
    assert j2 is not None and np.array_equal(r, r2)
    system(x, True)  # a second request is evaluated again
    assert system.system.jacobians == 2  # type: ignore[attr-defined]


def test_newton_on_step_and_its_fallback():
    kw = dict(tol=1e-12, residual_tol=1e-13, max_iter=30, stall_level=0.0,
              factorize=lambda j: (lambda b: np.linalg.solve(j, b)), chord=1e-3,
              line_search=False)
    res, on_step = newton_on_step(Counted(), np.ones(3), predict_iter=8, **kw)
    assert on_step and res.converged
    np.testing.assert_allclose(res.x**3 + res.x, [2.0, 10.0, 30.0], rtol=1e-12)
    short, on_step = newton_on_step(Counted(), np.ones(3), predict_iter=1, **kw)
    assert not on_step and short.converged and short.iterations > 1
    assert short.x == pytest.approx(res.x, rel=1e-12)
