"""The one solver registry (kinetic_fem/solve.py): every transient entry against exact
moments.

Parametrised over ``SOLVERS["transient-heated"]`` and ``SOLVERS["transient-cooling"]``:
registering a transient method adds it here.  Each runs the inelastic Maxwell model
(``kernel=0``), whose moment equations close
(:func:`kinetic_fem.solvers.maxwell.evolve_moments`, integrated to 1e-12), at a cheap
mesh, and must follow the exact T (relative) and a2 (absolute) within the tolerance of
``SPECS``: the global error measured for that option set (the numbers below) times
about 2-3 (heated: below ``rtol``, as its docstring promises; cooling: its ``rtol`` is
a local tolerance per step, default 1e-6, and the global error of a2 is about 5x it,
the same before and after the integrator's rewrite: 5.2e-6 then).
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.solve import PROBLEM_KINDS, SOLVERS, lookup_solver, register_solver
from kinetic_fem.solvers.maxwell import evolve_moments

# (kind, key) -> (options, (T relative, a2 absolute)).  Measured (spacing 0.5, cutoff 10,
# times 0.1 .. 0.6):
#   heated (alpha 0.5, friction 0.5, from T = 1, rtol 1e-4): T 1.4e-5, a2 2.1e-5
#     -> 4e-5, 5e-5 (1.1 CPU s).
#   cooling (alpha 0.5, from T = 1, rtol 1e-6): T 2.5e-6, a2 5.4e-6 -> 6e-6, 1.2e-5
#     (1.1 CPU s).
SPECS = {
    ("transient-heated", "fem"): ({"spacing": 0.5, "cutoff": 10.0, "rtol": 1e-4},
                                  (4e-5, 5e-5)),
    ("transient-cooling", "fem"): ({"spacing": 0.5, "cutoff": 10.0, "rtol": 1e-6},
                                   (6e-6, 1.2e-5)),
}
TIMES = [0.1, 0.3, 0.6]
ENTRIES = [(kind, key) for kind in ("transient-heated", "transient-cooling")
           for key in sorted(SOLVERS[kind])]


def test_one_registry_holds_steady_and_transient_kinds():
    # solvers register on first use: the steady ones with load_solvers, the transient ones
    # with kinetic_fem.evolve (run alone, nothing has used them yet)
    kf.load_solvers()
    import kinetic_fem.evolve  # noqa: F401
    assert set(SOLVERS) == set(PROBLEM_KINDS)
    assert SOLVERS["heated"] is kf.HEATED_SOLVERS and SOLVERS["cooling"] is kf.COOLING_SOLVERS
    for kind in PROBLEM_KINDS:
        assert SOLVERS[kind], f"no solver registered for {kind}"
    with pytest.raises(ValueError, match="unknown problem kind 'steady'"):
        register_solver("x", problem="steady")
    with pytest.raises(ValueError, match="unknown transient-heated method 'nope'"):
        kf.evolve_heated(0.5, times=[0.1], method="nope")
    with pytest.raises(ValueError, match="already registered"):
        register_solver("fem", problem="transient-cooling")(lambda *a, **k: None)


@pytest.mark.parametrize(("kind", "key"), ENTRIES)
def test_transient_follows_the_exact_maxwell_moments(kind, key):
    """Global error of T and a2 against the closed moment equations of the Maxwell
    model; for the default method also the counters of the integrator."""
    options, (tol_t, tol_a2) = SPECS.get((kind, key), ({}, (1e-4, 1e-4)))
    assert lookup_solver(kind, key) is SOLVERS[kind][key]
    if kind == "transient-heated":
        ev = kf.evolve_heated(0.5, kernel=0.0, friction=0.5, initial_temperature=1.0,
                              times=TIMES, method=key, **options)
        exact = evolve_moments(0.5, [0.0, *TIMES], friction=0.5, initial_temperature=1.0,
                               order=4)
    else:
        ev = kf.evolve_cooling(0.5, kernel=0.0, initial_temperature=1.0, times=TIMES,
                               method=key, **options)
        exact = evolve_moments(0.5, [0.0, *TIMES], diffusion=0.0, initial_temperature=1.0,
                               order=4)
    err_t = np.max(np.abs(np.asarray(ev.temperature) / exact.temperature[1:] - 1.0))
    err_a2 = np.max(np.abs(np.asarray(ev.a2) - exact.a2[1:]))
    assert err_t < tol_t and err_a2 < tol_a2, (err_t, err_a2)
    if key == "fem":   # the Jacobian is kept across steps: far fewer than steps
        extra = ev.info.extra
        assert extra["jacobians"] < extra["accepted"] / 2
