"""Tests of kinetic_fem.solve: the solver registry and the public entry points.

Contract tests parametrise over every registered solver, so a new solver is
checked automatically: its options are explicit keywords (a misspelt option raises
TypeError before any work), and parameters are validated before dispatch.
"""

import importlib
import pkgutil

import numpy as np
import pytest

import kinetic_fem
from kinetic_fem import VelocityDistribution
from kinetic_fem.gas import CoolingProblem, HeatedProblem
from kinetic_fem.solve import (
    COOLING_SOLVERS,
    HEATED_SOLVERS,
    register_solver,
    solve_cooling,
    solve_heated,
)

for _mod in pkgutil.iter_modules(kinetic_fem.__path__):  # register every solver
    if not _mod.name.startswith("_") and _mod.name not in {"cli"}:
        importlib.import_module(f"kinetic_fem.{_mod.name}")


@pytest.fixture
def dummy():
    """A registered toy solver that records what it was called with."""
    calls = []

    def solver(problem, *, n_v=11, tol=1e-8):
        calls.append((problem, n_v, tol))
        v = np.linspace(-5, 5, n_v)
        return VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="dummy-test",
                                                params=problem.as_dict())

    register_solver("dummy-test", problem="heated")(solver)
    register_solver("dummy-test", problem="cooling")(solver)
    yield calls
    HEATED_SOLVERS.pop("dummy-test")
    COOLING_SOLVERS.pop("dummy-test")


def test_dispatch_validates_and_passes_options(dummy):
    d = solve_heated(0.7, density=2, diffusion=3, method="dummy-test", n_v=21)
    problem, n_v, tol = dummy[-1]
    assert isinstance(problem, HeatedProblem) and n_v == 21 and tol == 1e-8
    assert d.params == {"problem": "heated", "alpha": 0.7, "density": 2.0, "diffusion": 3.0,
                        "gamma": 1.0}
    solve_cooling(0.7, method="dummy-test")
    assert isinstance(dummy[-1][0], CoolingProblem)


def test_bad_parameters_raise_before_the_solver_runs(dummy):
    with pytest.raises(ValueError, match="no steady state"):
        solve_heated(1.0, method="dummy-test")
    with pytest.raises(ValueError, match="diffusion"):
        solve_heated(0.5, diffusion=-1, method="dummy-test")
    with pytest.raises(TypeError, match="density"):
        solve_cooling(0.5, density="2", method="dummy-test")
    assert dummy == []


def test_unknown_method_lists_the_available_ones(dummy):
    with pytest.raises(ValueError, match=r"unknown heated method 'nope'; available: \[.*"
                                         r"'dummy-test'"):
        solve_heated(0.5, method="nope")
    with pytest.raises(ValueError, match="unknown cooling method"):
        solve_cooling(0.5, method=3)


def test_misspelt_option_raises_type_error(dummy):
    with pytest.raises(TypeError, match="n_vv"):
        solve_heated(0.5, method="dummy-test", n_vv=10)


def test_double_registration_is_refused(dummy):
    with pytest.raises(ValueError, match="already registered as 'dummy-test'"):
        register_solver("dummy-test", problem="heated")(lambda p: None)


@pytest.mark.parametrize("key", sorted(HEATED_SOLVERS))
def test_registered_heated_solvers_refuse_unknown_options(key):
    """Every registered solver: explicit keyword options, typos raise TypeError."""
    with pytest.raises(TypeError):
        solve_heated(0.5, method=key, no_such_option_xyz=1)


@pytest.mark.parametrize("key", sorted(COOLING_SOLVERS))
def test_registered_cooling_solvers_refuse_unknown_options(key):
    with pytest.raises(TypeError):
        solve_cooling(0.5, method=key, no_such_option_xyz=1)
