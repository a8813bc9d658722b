"""Tests of the regime table of the FEM cooling state (kinetic_fem.solvers.fem.regimes)."""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.model import CoolingProblem, SaturatingKernel, UnsupportedModelError
from kinetic_fem.solvers.fem import regimes as fr

KERNELS = (0.0, 0.5, 1.0, 1.5, 2.0)
# a grid over [0, 1 - 1e-6] with every threshold of the table and its neighbours
_THRESHOLDS = (0.5, 0.9, 0.965, 1.0 - 3e-3, 1.0 - 5e-4, 1.0 - 1e-4)
ALPHAS = np.unique(np.concatenate([
    np.linspace(0.0, 0.99, 100), 1.0 - np.geomspace(1e-2, 1e-6, 41),
    [t + d for t in _THRESHOLDS for d in (-1e-9, 0.0, 1e-9)]]))
_VERTICES = np.linspace(-8.0, 8.0, 33)
OPTIONS = (
    fr.CoolingOptions(), fr.CoolingOptions(order=2), fr.CoolingOptions(order=3),
    fr.CoolingOptions(spacing=0.1), fr.CoolingOptions(cutoff=20.0),
    fr.CoolingOptions(vertices=_VERTICES), fr.CoolingOptions(resolution=0.1),
    fr.CoolingOptions(order=2, resolution=0.1), fr.CoolingOptions(stored=False),
    fr.CoolingOptions(sequence=False), fr.CoolingOptions(spacing=0.1, cutoff=20.0),
)


def test_table_is_a_partition():
    """Exactly one regime applies to every power-law kernel, alpha in [0, 1 - 1e-6] and
    set of options (11 variants), and select() returns it; every regime is reached."""
    reached = set()
    for gamma in KERNELS:
        for alpha in ALPHAS:
            problem = CoolingProblem.from_parameters(float(alpha), kernel=gamma)
            for options in OPTIONS:
                hits = [r for r in fr.REGIMES if r.applies(problem, options)]
                assert len(hits) == 1, (gamma, alpha, options, hits)
                assert fr.select(problem, options) is hits[0]
                reached.add(type(hits[0]))
    assert reached == {type(r) for r in fr.REGIMES}


def test_saturating_kernel_is_refused_before_the_table():
    """A kernel without a scaled state never reaches the table (CoolingProblem refuses)."""
    with pytest.raises(UnsupportedModelError, match="no scaled steady state"):
        CoolingProblem.from_parameters(0.9, kernel=SaturatingKernel(1.0))


@pytest.mark.parametrize("alpha, gamma, expected", [
    (0.7, 0.0, fr.MaxwellTail), (0.9, 2.0, fr.Gamma2Anchored), (0.999, 1.5, fr.NearElasticHard),
    (0.95, 1.0, fr.HumpBand), (0.99, 1.0, fr.HumpChain), (0.9, 1.5, fr.HardKernelChain),
    (0.2, 0.5, fr.StrongInelastic), (0.7, 1.0, fr.GenericNewton)])
def test_default_options_pick(alpha, gamma, expected):
    """The table picks the regime its docstring names for the default options."""
    problem = CoolingProblem.from_parameters(alpha, kernel=gamma)
    assert type(fr.select(problem, fr.CoolingOptions())) is expected


# one cheap problem per regime (0.1 to 1.3 CPU s each; NearElasticHard 32 s)
CHEAP = [
    ("MaxwellTail", 0.0, 0.7, {"order": 2, "spacing": 0.16}),
    ("Gamma2Anchored", 2.0, 0.9, {}),
    ("HumpBand", 1.0, 0.95, {}),
    ("HumpChain", 1.0, 0.97, {}),
    ("MaxwellTruncated", 0.0, 0.5, {"spacing": 0.16, "cutoff": 1e8}),
    ("HardKernelChain", 2.0, 0.9, {"spacing": 0.2}),
    ("StrongInelastic", 1.0, 0.3, {"spacing": 0.2, "order": 2}),
    ("GenericNewton", 1.0, 0.7, {"spacing": 0.2, "order": 2}),
    pytest.param("NearElasticHard", 1.5, 0.998, {}, marks=pytest.mark.slow),
]


@pytest.mark.parametrize("name, gamma, alpha, options", CHEAP)
def test_each_regime_solves(name, gamma, alpha, options):
    """Each regime, called directly, converges to a state that satisfies the energy
    identity (not imposed by the solver) to 1e-6 (measured: 1.6e-8 for gamma = 2 on
    spacing 0.2, 5e-9 or less for the others)."""
    problem = CoolingProblem.from_parameters(alpha, kernel=gamma)
    opts = fr.CoolingOptions(**options)
    regime = fr.select(problem, opts)
    assert type(regime).__name__ == name
    state = regime.solve(problem, opts, fr.Run())
    assert state.info.converged
    assert state.energy_identity() == pytest.approx(state.zeta, rel=1e-6)


def test_strong_inelastic_walks_its_path_with_the_continuation_driver(monkeypatch):
    """Below alpha 0.5 the state is continued down from the state at 0.5: one step with
    the default step (0.5), several with a smaller one; the converged state does not
    depend on the path (Newton's tolerance 1e-9)."""
    problem = CoolingProblem.from_parameters(0.4, kernel=1.0)
    options = fr.CoolingOptions(order=2, spacing=0.5, sequence=False, tol=1e-9)
    regime = fr.select(problem, options)
    assert isinstance(regime, fr.StrongInelastic)
    assert regime.path(problem, options) == [0.5]
    one_step = fr.solve_state(problem, options)
    monkeypatch.setattr(fr.StrongInelastic, "step", 0.04)
    path = regime.path(problem, options)
    assert path[0] == 0.5 and len(path) == 3
    steps = -np.diff([*path, 0.4])
    assert np.all(steps > 0.0) and np.all(steps <= 0.04 + 1e-12)
    three_steps = fr.solve_state(problem, options)
    assert three_steps.zeta == pytest.approx(one_step.zeta, rel=1e-8)
    np.testing.assert_allclose(three_steps.u, one_step.u, rtol=0, atol=1e-6)
