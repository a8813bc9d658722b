"""The default element degree of the heated FEM states by model (issue 16)."""

from __future__ import annotations

import pytest

import kinetic_fem as kf
from kinetic_fem.exceptions import ConvergenceError
from kinetic_fem.solvers.fem import heated as fem
from kinetic_fem.solvers.fem.defaults import default_order, scaled_model


@pytest.mark.parametrize(("alpha", "kernel", "friction", "order"), [
    (0.5, 1.0, 0.0, 3), (0.5, 0.0, 0.0, 3), (0.5, 0.5, 0.0, 3), (0.5, 2.0, 0.0, 2),
    (0.5, 1.0, 1.0, 3), (0.5, 2.0, 1.0, 2), (0.99, 0.0, 0.0, 3), (0.99, 0.0, 1.0, 3),
    (0.999, 0.5, 0.0, 3), (0.99, 2.0, 0.0, 2),
    (kf.ViscoelasticRestitution(0.2), 1.0, 0.0, 2)])
def test_default_order_by_model(alpha, kernel, friction, order):
    problem = kf.HeatedProblem.from_parameters(alpha, kernel=kernel, friction=friction)
    assert default_order(scaled_model(problem)) == order


def test_p3_default_falls_back_to_p2(monkeypatch):
    solve = fem._widened_solve

    def failing_p3(alpha, scaled, paper, order, *args, **kwargs):
        if order == 3:
            raise ConvergenceError("P3 refused (test)")
        return solve(alpha, scaled, paper, order, *args, **kwargs)

    assert kf.solve_heated(0.6, kernel=0.0).info.extra["order"] == 3
    monkeypatch.setattr(fem, "_widened_solve", failing_p3)
    dist = kf.solve_heated(0.6, kernel=0.0)
    assert dist.info.extra["order"] == 2 and dist.info.converged
