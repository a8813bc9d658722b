"""Tests of the shared Newton driver :mod:`kinetic_fem.solvers.newton`."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse
from scipy.sparse.linalg import LinearOperator

from kinetic_fem.run_info import RunInfo
from kinetic_fem.solvers.newton import (
    NewtonOptions,
    NewtonResult,
    PseudoTransient,
    newton,
    run_info,
)


def rosenbrock_system(x, jacobian):
    """``r = (10 (x1 - x0^2), 1 - x0)``: root (1, 1), Jacobian known."""
    r = np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])
    jac = np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]]) if jacobian else None
    return r, jac


def test_quadratic_convergence_on_a_known_system():
    """Newton on ``x0^2 + x1^2 = 4, x0 = x1`` (root sqrt2 (1, 1)): errors square each step."""
    root = math.sqrt(2.0)

    def fun(x, jacobian):
        r = np.array([x[0] ** 2 + x[1] ** 2 - 4.0, x[0] - x[1]])
        return r, np.array([[2 * x[0], 2 * x[1]], [1.0, -1.0]])

    res = newton(fun, [3.0, 1.0], tol=1e-15, max_iter=20)
    assert res.converged and isinstance(res, NewtonResult)
    assert np.max(np.abs(res.x - root)) < 4e-16
    h = [v for v in res.history if v > 1e-13]
    # quadratic: r_{k+1} <= C r_k^2 with a modest C once in the basin
    ratios = [h[k + 1] / h[k] ** 2 for k in range(1, len(h) - 1)]
    assert max(ratios) < 1.0
    assert res.iterations <= 7


def test_sparse_matrix_free_and_user_solvers_agree():
    """Dense, sparse, LinearOperator and callable Jacobians, and a user solver."""
    n = 30
    lap = scipy.sparse.diags([-1.0, 2.2, -1.0], [-1, 0, 1], shape=(n, n)).tocsr()
    b = np.linspace(1.0, 2.0, n)

    def make(kind):
        def fun(x, jacobian):
            r = lap @ x + x**3 - b
            d = scipy.sparse.diags(3 * x**2)
            jac = (lap + d).tocsr()
            if kind == "dense":
                return r, jac.toarray()
            if kind == "operator":
                return r, LinearOperator((n, n), matvec=lambda v: jac @ v, dtype=float)
            if kind == "callable":
                return r, lambda v: jac @ v
            return r, jac
        return fun

    results = {k: newton(make(k), np.zeros(n), tol=1e-13)
               for k in ("dense", "sparse", "operator", "callable")}
    results["user"] = newton(make("dense"), np.zeros(n), tol=1e-13,
                             linear_solver=lambda j, rhs: np.linalg.solve(j, rhs))
    ref = results["dense"].x
    for key, res in results.items():
        assert res.converged, key
        assert np.max(np.abs(res.x - ref)) < 1e-12, key


def test_line_search_rescues_a_divergent_newton():
    """``arctan x = 0`` from ``x = 3``: full steps overshoot and diverge, Armijo converges."""
    def fun(x, jacobian):
        with np.errstate(over="ignore"):   # the undamped run overflows x**2
            return np.arctan(x), np.diag(1.0 / (1.0 + x**2))

    plain = newton(fun, [3.0], tol=1e-12, max_iter=30, line_search=False)
    assert not plain.converged
    damped = newton(fun, [3.0], tol=1e-12, max_iter=30)
    assert damped.converged and abs(damped.x[0]) < 1e-12
    assert damped.iterations < 15


def test_rosenbrock_with_column_and_row_scales():
    res = newton(rosenbrock_system, [-1.2, 1.0], tol=1e-14,
                 row_scale=lambda x: np.array([10.0, 1.0]),
                 column_scale=lambda x: np.maximum(np.abs(x), 1.0))
    assert res.converged
    assert np.allclose(res.x, 1.0, rtol=0, atol=1e-14)


def noisy(x, jacobian):
    """``x^2 - 2`` plus a deterministic +-1e-10 'round-off' that flips sign every 1e-12 in x.

    Near the root ``x^2 - 2`` changes by 3e-12 per cell, so ``|r|`` never falls below
    about 1e-10: the floor Newton must recognise."""
    r = x**2 - 2.0 + 1e-10 * np.where(np.floor(x * 1e12) % 2 == 0, 1.0, -1.0)
    return r, np.diag(2.0 * x)


@pytest.mark.parametrize("criterion", ["residual", "step"])
def test_stall_at_round_off_reported_converged(criterion):
    """Below ``stall_level`` a measure that stops decreasing is the floor: converged."""
    res = newton(noisy, [1.0], tol=1e-15, max_iter=40, criterion=criterion,
                 stall_level=1e-6)
    assert res.converged
    assert "stalled at round-off" in res.message
    assert abs(res.x[0] - math.sqrt(2.0)) < 1e-9
    assert res.residual < 1e-9
    # without the stall rule the same run is not converged (tolerance out of reach)
    strict = newton(noisy, [1.0], tol=1e-15, max_iter=40, criterion=criterion)
    assert not strict.converged
    assert "not converged" in strict.message or "stopped" in strict.message


def test_step_criterion_and_update_hook():
    """A multiplicative update ``x -> x e^dx`` (Newton in ln x) keeps x positive."""
    def fun(x, jacobian):
        return np.log(x) - 1.0, np.eye(1)   # derivative in ln x is 1

    res = newton(fun, [1e-3], tol=1e-12, criterion="step",
                 update=lambda x, dx: x * np.exp(dx))
    assert res.converged and abs(res.x[0] - math.e) < 1e-12
    assert res.step < 1e-12


def test_non_finite_residual_raises_a_clear_error():
    def fun(x, jacobian):
        return np.array([np.nan, 1.0]), np.eye(2)

    with pytest.raises(ValueError, match="not finite"):
        newton(fun, [0.0, 0.0], tol=1e-10)


def test_non_finite_trial_is_backtracked():
    """``sqrt(x) - 1`` is NaN for x < 0: the first full step from x = 9 lands there."""
    def fun(x, jacobian):
        with np.errstate(invalid="ignore"):
            return np.sqrt(x) - 1.0, np.diag(0.5 / np.sqrt(np.abs(x)))

    res = newton(fun, [9.0], tol=1e-13, max_iter=40)
    assert res.converged and abs(res.x[0] - 1.0) < 1e-12


def test_singular_system_stops_not_converged():
    def fun(x, jacobian):
        return np.array([1.0, 1.0]), np.zeros((2, 2))

    res = newton(fun, [0.0, 0.0], tol=1e-10)
    assert not res.converged and "singular" in res.message


@pytest.mark.parametrize("kw", [{"tol": 0.0}, {"tol": 1e-8, "max_iter": -1},
                                {"tol": 1e-8, "criterion": "both"},
                                {"tol": 1e-8, "armijo": 1.0},
                                {"tol": 1e-8, "min_damping": 0.0},
                                {"tol": 1e-8, "on_failure": "retry"},
                                {"tol": 1e-8, "stall_level": -1.0}])
def test_bad_options_raise(kw):
    with pytest.raises(ValueError, match="not allowed"):
        newton(rosenbrock_system, [0.0, 0.0], **kw)


def test_run_info_fields():
    res = newton(rosenbrock_system, [0.5, 0.5], tol=1e-12)
    info = run_info(res, wall_time=0.25, extra={"n": 2})
    assert isinstance(info, RunInfo)
    assert (info.converged, info.iterations, info.residual, info.wall_time) == \
        (res.converged, res.iterations, res.residual, 0.25)
    assert info.extra == {"n": 2} and info.message == res.message


@pytest.mark.parametrize("line_search", [True, False])
def test_jacobian_only_where_a_step_follows(line_search):
    """One Jacobian per linear solve: none at the converged point."""
    calls = {True: 0, False: 0}

    def fun(x, jacobian):
        calls[jacobian] += 1
        return x**2 - 2.0, np.diag(2.0 * x) if jacobian else None

    res = newton(fun, [1.0], tol=1e-14, line_search=line_search)
    assert res.converged
    if line_search:   # x0, then one per further step; trial residuals are reused
        assert calls[True] == res.iterations
        assert calls[False] == res.iterations
    else:             # the full step is the next iterate: its Jacobian comes with it
        assert calls[True] == res.iterations + 1
        assert calls[False] == 0


def test_chord_steps_reuse_the_factorisation():
    """With ``chord``: below the chord level the factorisation is reused (fewer Jacobians,
    same root to round-off); a chord step that contracts too slowly refreshes it."""
    target = np.array([1.0, 2.0, 3.0])
    calls = {"jac": 0, "factor": 0}

    def fun(x, jacobian):
        r = x**3 + x - (target**3 + target)
        if jacobian:
            calls["jac"] += 1
        return r, np.diag(3 * x**2 + 1.0) if jacobian else None

    def factorize(j):
        calls["factor"] += 1
        lu = scipy.linalg.lu_factor(j)
        return lambda b: scipy.linalg.lu_solve(lu, b)

    plain = newton(fun, np.ones(3), tol=1e-13, factorize=factorize)
    plain_jac = calls["jac"]
    calls.update(jac=0, factor=0)
    chord = newton(fun, np.ones(3), tol=1e-13, factorize=factorize, chord=1e-2)
    assert plain.converged and chord.converged
    np.testing.assert_allclose(chord.x, target, rtol=1e-14)
    np.testing.assert_allclose(plain.x, target, rtol=1e-14)
    assert calls["factor"] < plain_jac
    assert calls["jac"] == calls["factor"]
    # a hopeless chord rate (every chord step "too slow") still converges, by refreshes
    slow = newton(fun, np.ones(3), tol=1e-13, factorize=factorize, chord=1e-2,
                  chord_rate=1e-12)
    assert slow.converged


def test_chord_contracted_reuses_the_factors_in_the_quadratic_regime():
    """With ``chord_contracted``: a full step above ``chord`` that contracted the one
    before by ``chord_rate**2`` is followed by chord steps (one Jacobian fewer here, the
    same root); a step without that contraction (the first) is not."""
    target = np.array([1.0, 2.0, 3.0])
    calls = {"jac": 0}

    def fun(x, jacobian):
        if jacobian:
            calls["jac"] += 1
        return x**3 + x - (target**3 + target), np.diag(3 * x**2 + 1.0) if jacobian else None

    def factorize(j):
        lu = scipy.linalg.lu_factor(j)
        return lambda b: scipy.linalg.lu_solve(lu, b)

    runs = {}
    for contracted in (0.0, 0.5):
        calls["jac"] = 0
        res = newton(fun, np.full(3, 1.5), tol=1e-13, factorize=factorize, chord=1e-6,
                     chord_rate=0.1, chord_contracted=contracted, criterion="step")
        assert res.converged
        np.testing.assert_allclose(res.x, target, rtol=1e-14)
        runs[contracted] = (calls["jac"], list(res.history))
    (plain, steps), (fewer, _) = runs[0.0], runs[0.5]
    # the plain run's steps: a full step below 0.5 contracting the one before by 1e-2
    assert any(b < 0.5 and b <= 1e-2 * a for a, b in zip(steps, steps[1:], strict=False))
    assert fewer < plain


@pytest.mark.parametrize("kw", [dict(chord=-1.0), dict(chord=1e-3, chord_rate=1.5),
                                dict(chord=1e-3)])
def test_bad_chord_options_raise(kw):
    with pytest.raises(ValueError, match="chord"):
        newton(rosenbrock_system, [0.0, 0.0], tol=1e-10, **kw)


def test_options_object_and_keywords_give_the_same_iterates():
    opts = NewtonOptions(tol=1e-12, criterion="step", line_search=False)
    by_object = newton(rosenbrock_system, [0.0, 0.0], opts)
    by_keywords = newton(rosenbrock_system, [0.0, 0.0], tol=1e-12, criterion="step",
                         line_search=False)
    assert by_object.history == by_keywords.history and by_object.converged
    np.testing.assert_array_equal(by_object.x, by_keywords.x)
    # a keyword overrides the object
    short = newton(rosenbrock_system, [0.0, 0.0], opts, max_iter=1)
    assert short.iterations == 1 and not short.converged


def test_unknown_option_raises_type_error():
    with pytest.raises(TypeError, match="tolerance"):
        newton(rosenbrock_system, [0.0, 0.0], tol=1e-10, tolerance=1e-3)


def test_pseudo_transient_reaches_the_root_of_a_stiff_system():
    """``r(x) = 8 - x^3`` from x = 0.1 (Jacobian -0.03: the plain full step jumps to
    x = 89): implicit Euler in the pseudo-time of dx/dtau = r(x), whose attractor is the
    root x = 2, walks up to it, and ends as Newton."""

    def fun(x, jacobian):
        return 8.0 - x**3, np.diag(-3.0 * x**2) if jacobian else None

    pt = PseudoTransient(first_step=0.05, mass=lambda x: np.eye(1))
    res = newton(fun, [0.1], tol=1e-13, max_iter=200, pseudo_time=pt)
    assert res.converged and abs(res.x[0] - 2.0) < 1e-13
    steps = np.array(res.history)
    assert steps[0] < 0.5  # the first step, damped by the pseudo-time term: 8 / 20.03
    assert len(steps) > 3 and steps[-1] < 1e-13
    plain = newton(fun, [0.1], tol=1e-13, max_iter=1, line_search=False)
    assert plain.x[0] > 50.0  # the undamped Newton step overshoots


def test_predicted_newton_step_is_taken_when_the_residual_is_at_round_off():
    """The second equation's residual (scale 1e-7) falls below the first's round-off
    (4e-16) while its step is still 9e-10 (> tol): the line search backtracks on noise
    and the stall rule ends 9e-10 away from the root; ``predict_newton`` takes the step,
    whose chord prediction (9e-10**2 / 3e-3 = 3e-16) is far below tol."""

    def fun(x, jacobian):
        e = x[1] - 3.0
        r = np.array([x[0] ** 2 - 2.0, 1e-7 * (e + 1e-4 * e * e)])
        jac = np.array([[2.0 * x[0], 0.0], [0.0, 1e-7 * (1.0 + 2e-4 * e)]])
        return r, jac if jacobian else None

    def factorize(jac):
        lu = scipy.linalg.lu_factor(jac)
        return lambda b: scipy.linalg.lu_solve(lu, b)

    options = NewtonOptions(tol=1e-11, criterion="step", factorize=factorize, chord=1e-3,
                            predict=0.01, stall_level=1e-8)
    stalled = newton(fun, [math.sqrt(2.0), 3.003], options)
    assert stalled.converged and "stalled" in stalled.message
    assert abs(stalled.x[1] - 3.0) > 1e-10
    taken = newton(fun, [math.sqrt(2.0), 3.003], options, predict_newton=True)
    assert taken.converged and "Newton-predicted" in taken.message
    assert abs(taken.x[1] - 3.0) < 1e-15 and taken.iterations == 2
    # the first step (no previous full step to predict from) is never taken blindly
    first = newton(fun, [math.sqrt(2.0), 3.0 + 1e-9], options, predict_newton=True)
    assert "Newton-predicted" not in first.message
